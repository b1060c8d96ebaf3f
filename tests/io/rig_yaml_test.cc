#include "libbead/io/rig_yaml.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/rig_keys.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

const char* kSpecExample = R"(name: bcs-blue-gantry          # free text
encoder:
  counts_per_rev: 20480
  bits: 32
  direction: 1
wheel:
  diameter_mm: 254.762
offset:
  counts: 3071.5
sensor:
  reference_areas_mm: [[-24.0, -12.0], [12.0, 24.0]]
  laser_origin_mm: [0.0, 95.0]
operator: kept-but-ignored
)";

TEST(RigYaml, ReadsTheSpecExample) {
  const Rig rig = ParseRig(kSpecExample, "rig.yaml").rig;
  EXPECT_EQ(rig.name, "bcs-blue-gantry");
  EXPECT_EQ(rig.encoder.counts_per_rev, 20480);
  EXPECT_EQ(rig.encoder.bits, 32);
  EXPECT_EQ(rig.encoder.direction, 1);
  EXPECT_DOUBLE_EQ(rig.wheel_diameter_mm, 254.762);
  EXPECT_DOUBLE_EQ(rig.offset_counts, 3071.5);
  EXPECT_DOUBLE_EQ(rig.reference_left.x_min_mm, -24.0);
  EXPECT_DOUBLE_EQ(rig.reference_right.x_max_mm, 24.0);
  ASSERT_TRUE(rig.laser_origin.has_value());
  EXPECT_DOUBLE_EQ(rig.laser_origin->z_mm, 95.0);
  // One count of a 254.762 mm wheel with 20480 counts per turn.
  EXPECT_NEAR(rig.MmPerCount(), M_PI * 254.762 / 20480, 1e-15);
}

// Each broken rig names the key and the line, and what to do.
TEST(RigYaml, ErrorsNameTheKeyAndLine) {
  struct Case {
    std::string from, to, expect;
  };
  const std::vector<Case> cases = {
      {"  counts_per_rev: 20480\n", "", "encoder.counts_per_rev: missing key"},
      {"20480", "-5", "encoder.counts_per_rev: must be positive"},
      {"bits: 32", "bits: 3", "line 4: encoder.bits"},
      {"direction: 1", "direction: 2", "encoder.direction: must be 1 or -1"},
      {"254.762", "abc", "line 7: wheel.diameter_mm: must be a number, got 'abc'"},
      {"counts: 3071.5", "counts: .nan", "offset.counts: must be a finite number"},
      {"[12.0, 24.0]", "[-13.0, 24.0]", "the two reference areas overlap"},
      {"[-24.0, -12.0]", "[-12.0, -24.0]", "reference_areas_mm[0]: is empty"},
      {"[[-24.0, -12.0], [12.0, 24.0]]", "[[-24.0, -12.0]]", "must hold exactly two x ranges"},
      {"[0.0, 95.0]", "[0.0]", "laser_origin_mm: must be a pair"},
      {"wheel:\n", "wheel: [\n", "not valid YAML"},
      // The wheel calibration's keys: both or neither, in range.
      {"254.762", "254.762\n  eccentricity_mm: 0.5", "wheel.eccentricity_phase_deg: missing key"},
      {"254.762", "254.762\n  eccentricity_mm: -0.5\n  eccentricity_phase_deg: 10",
       "wheel.eccentricity_mm: must be 0 or more and under a tenth of the diameter"},
      {"254.762", "254.762\n  eccentricity_mm: 0.5\n  eccentricity_phase_deg: 900",
       "wheel.eccentricity_phase_deg: must be an angle within +-360 degrees"},
  };
  for (const Case& c : cases) {
    std::string text = kSpecExample;
    const auto pos = text.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.from;
    text.replace(pos, c.from.size(), c.to);
    try {
      ParseRig(text, "my-rig.yaml");
      ADD_FAILURE() << "accepted: " << c.expect;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("my-rig.yaml: "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(ParseRig("", "empty.yaml"), Error);
  EXPECT_THROW(ParseRig("- a\n- b\n", "list.yaml"), Error);
  EXPECT_THROW(ReadRigFile("/nonexistent/rig.yaml"), Error);
}

// Rewriting a rig with a new offset keeps every key the user had.
TEST(RigYaml, RewriteKeepsUnknownKeysAndIsAtomic) {
  test::TempDir dir;
  const std::string path = dir / "rig.yaml";
  test::WriteText(path, kSpecExample);
  RigFile file = ReadRigFile(path);
  file.rig.offset_counts = 3080.25;
  WriteRigFile(path, file);
  const RigFile again = ReadRigFile(path);
  EXPECT_DOUBLE_EQ(again.rig.offset_counts, 3080.25);
  EXPECT_EQ(again.document["operator"].as<std::string>(), "kept-but-ignored");
  EXPECT_DOUBLE_EQ(again.rig.wheel_diameter_mm, 254.762);
  // Nothing but the rig is left in the folder (no temporary files).
  int entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) entries += entry.is_regular_file();
  EXPECT_EQ(entries, 1);
  // A write into a missing folder fails with a message, leaving nothing.
  EXPECT_THROW(WriteRigFile(dir / "missing/rig.yaml", file), Error);
}

// A key one edit from a listed one is a typo that silently changes the
// answer (no laser origin: another hidden area): named with the key meant,
// at its line. A key nowhere near a listed one is kept without a word (the
// format's promise), and the spec's own example warns of nothing.
TEST(RigYaml, AKeyOneEditFromAListedOneIsNamedWithTheKeyMeant) {
  EXPECT_TRUE(ParseRig(kSpecExample, "rig.yaml").warnings.empty());
  std::string text = kSpecExample;
  text.replace(text.find("laser_origin_mm"), 15, "laser_orign_mm");
  text.replace(text.find("name:"), 5, "nmae:");
  const RigFile file = ParseRig(text, "my-rig.yaml");
  EXPECT_FALSE(file.rig.laser_origin.has_value());  // still read as the format says: ignored
  ASSERT_EQ(file.warnings.size(), 2u) << (file.warnings.empty() ? "" : file.warnings[0]);
  EXPECT_NE(file.warnings[0].find("my-rig.yaml: line 1: nmae"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[0].find("did you mean 'name'?"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[1].find("line 12: sensor.laser_orign_mm"), std::string::npos) << file.warnings[1];
  EXPECT_NE(file.warnings[1].find("'sensor.laser_origin_mm'"), std::string::npos) << file.warnings[1];
  // Two edits away, or another section's key: not a typo of a listed key.
  EXPECT_TRUE(ParseRig(std::string(kSpecExample) + "sensr_note: x\ncount: 3\n", "r.yaml").warnings.empty());
  EXPECT_EQ(EditDistance("laser_orign_mm", "laser_origin_mm"), 1u);
  EXPECT_EQ(EditDistance("bist", "bits"), 1u);  // two neighbours swapped: one edit
  EXPECT_EQ(EditDistance("offest", "offset"), 1u);
  EXPECT_GT(EditDistance("operator", "offset"), 1u);
}

// Units other than millimetres would change what every number means: the
// file is refused at the key, never read as if in mm.
TEST(RigYaml, UnitsOtherThanMillimetresAreRefused) {
  EXPECT_NO_THROW(ParseRig(std::string(kSpecExample) + "units: mm\n", "r.yaml"));
  for (const std::string units : {"units: inch\n", "units: [mm]\n"}) {
    try {
      ParseRig(std::string(kSpecExample) + units, "r.yaml");
      ADD_FAILURE() << "accepted " << units;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("r.yaml: line 14: units: is "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("millimetres"), std::string::npos) << e.what();
    }
  }
  std::string in_section = kSpecExample;
  in_section.replace(in_section.find("  counts: 3071.5"), 16, "  counts: 3071.5\n  units: inch");
  EXPECT_THROW(ParseRig(in_section, "r.yaml"), Error);
}

}  // namespace
}  // namespace bead
