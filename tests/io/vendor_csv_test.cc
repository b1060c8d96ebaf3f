// Vendor CSV exports: a real one (testdata/realdata/bead-observer, a laser
// line profiler over the top of a thin wall, no reference surface in view)
// and malformed ones. The import keeps every point as the file has it, z
// turned from distance into height; measuring such profiles gives no
// number, and says why, instead of inventing a reference.
#include "libbead/io/vendor_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "libbead/core/error.h"
#include "libbead/profile/measure_block.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

const std::string kReal =
    std::string(BEAD_SOURCE_DIR) + "/testdata/realdata/bead-observer/Representative_Layer_raw_points.csv";

ImportColumns RealColumns() { return Columns("ScanID", "Timestamp", "X", "Z", "", 1.0, true); }

// The rows of the real file, parsed independently of the importer.
struct Row {
  long scan;
  double t, x, z;
};
std::vector<Row> RealRows() {
  std::ifstream in(kReal);
  std::string line;
  std::getline(in, line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[7];
    for (auto& v : f) std::getline(ss, v, ',');
    rows.push_back({std::stol(f[1]), std::stod(f[2]), std::stod(f[5]), std::stod(f[6])});
  }
  return rows;
}

TEST(VendorCsv, RealExportKeepsEveryPointWithDistanceTurnedIntoHeight) {
  const std::vector<Row> rows = RealRows();
  const ImportedRun imported = ReadVendorCsv(kReal, RealColumns());
  const ProfileBlock& b = imported.run.profiles;
  ASSERT_EQ(imported.rows, rows.size());
  ASSERT_EQ(b.size(), 399u);  // ScanID 1..399, as the file's README says
  EXPECT_FALSE(b.shared_x);
  EXPECT_TRUE(EncoderAbsent(imported.run));
  // Row by row: the same x, z = -distance (float rounding of the file's
  // four decimals), in the file's order; the profile's time is its rows'.
  std::size_t i = 0, profile = 0, k = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (r > 0 && rows[r].scan != rows[r - 1].scan) ++profile, k = 0;
    const ProfileView v = b.view(profile);
    ASSERT_LT(k, v.x_mm.size());
    EXPECT_NEAR(v.x_mm[k], rows[r].x, 1e-6 * std::abs(rows[r].x)) << "row " << r;
    EXPECT_NEAR(v.z_mm[k], -rows[r].z, 1e-6 * std::abs(rows[r].z)) << "row " << r;
    EXPECT_DOUBLE_EQ(v.t_s, rows[r].t) << "row " << r;
    ++k, ++i;
  }
  EXPECT_EQ(profile + 1, b.size());
  EXPECT_EQ(i, rows.size());
  // Shorter profiles are padded with NaN to the longest (56 points).
  EXPECT_EQ(b.points, 56u);
}

// The wall top fills the view: no x falls in the rig's reference areas
// either side, so no profile has a line to measure against. Profiles with
// fewer than 10 points are too few; the others have no reference.
TEST(VendorCsv, RealExportWithoutReferenceSurfaceGivesNoNumber) {
  const ProfileBlock b = ReadVendorCsv(kReal, RealColumns()).run.profiles;
  const ReferenceArea left{-24.0, -12.0}, right{12.0, 24.0};
  const auto geometry = MeasureProfiles(b.size(), [&](std::size_t i) { return b.view(i); }, left, right, {});
  const ProfileOptions defaults;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const ProfileView v = b.view(i);
    int points = 0;
    for (std::size_t k = 0; k < v.z_mm.size(); ++k) points += std::isfinite(v.z_mm[k]);
    EXPECT_FALSE(geometry[i].valid()) << "profile " << i;
    EXPECT_TRUE(std::isnan(geometry[i].area_mm2)) << "profile " << i;
    EXPECT_EQ(geometry[i].status,
              points < defaults.bead.min_profile_points ? ProfileStatus::kTooFewPoints : ProfileStatus::kNoReference)
        << "profile " << i << " with " << points << " points";
  }
}

TEST(VendorCsv, ImportSurvivesTheRunArchive) {
  test::TempDir dir;
  const RunArchive run = ReadVendorCsv(kReal, RealColumns()).run;
  WriteRunArchive(dir / "layer.h5", run);
  const RunArchive back = ReadRunArchive(dir / "layer.h5");
  EXPECT_TRUE(EncoderAbsent(back));
  ASSERT_EQ(back.profiles.size(), run.profiles.size());
  for (std::size_t i = 0; i < run.profiles.size(); ++i) {
    const ProfileView a = run.profiles.view(i), c = back.profiles.view(i);
    ASSERT_EQ(a.t_s, c.t_s);
    for (std::size_t k = 0; k < a.z_mm.size(); ++k) {
      ASSERT_TRUE(a.z_mm[k] == c.z_mm[k] || (std::isnan(a.z_mm[k]) && std::isnan(c.z_mm[k])));
      ASSERT_TRUE(a.x_mm[k] == c.x_mm[k] || (std::isnan(a.x_mm[k]) && std::isnan(c.x_mm[k])));
    }
  }
}

TEST(VendorCsv, EncoderColumnAndTimeScaleAreUsed) {
  test::TempDir dir;
  test::WriteText(dir / "v.csv",
                  "ms,id,enc,height,pos\n"
                  "10,7,100,0.5,-1\n10,7,100,0.6,0\n10,7,100,0.5,1\n"
                  "15,8,140,0.4,-1\n15,8,140,,0\n");
  const ImportedRun imported = ReadVendorCsv(dir / "v.csv", Columns("id", "ms", "pos", "height", "enc", 1e-3, false));
  const ProfileBlock& b = imported.run.profiles;
  ASSERT_EQ(b.size(), 2u);
  EXPECT_FALSE(EncoderAbsent(imported.run));
  EXPECT_EQ(b.encoder, (std::vector<int64_t>{100, 140}));
  EXPECT_DOUBLE_EQ(b.t_s[0], 0.010);
  EXPECT_DOUBLE_EQ(b.t_s[1], 0.015);
  EXPECT_FLOAT_EQ(b.view(0).z_mm[1], 0.6f);    // height as it is
  EXPECT_TRUE(std::isnan(b.view(1).z_mm[1]));  // an empty field: no point
  EXPECT_TRUE(std::isnan(b.view(1).z_mm[2]));  // padding
}

TEST(VendorCsv, MalformedExportsAreRejectedWithFileLineAndColumn) {
  test::TempDir dir;
  const ImportColumns columns = Columns("id", "t", "x", "z", "", 1.0, false);
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"empty.csv", "", "empty file"},
      {"header-only.csv", "id,t,x,z\n", "holds no point rows"},
      {"missing-column.csv", "id,t,x,height\n1,0,0,0\n", "no column 'z' for the z (the header has: id, t, x, height)"},
      {"twice.csv", "id,t,x,z,z\n1,0,0,0,0\n", "more than one column 'z'"},
      {"text-x.csv", "id,t,x,z\n1,0,0,0\n1,0,abc,0\n", "line 3: column 3 (x) is 'abc', not a number"},
      {"text-id.csv", "id,t,x,z\nA,0,0,0\n", "line 2: column 1 (id) is 'A', not a whole number"},
      {"apart.csv", "id,t,x,z\n1,0,0,0\n2,1,0,0\n1,0,1,0\n", "line 4: rows of profile 1 are not together"},
      {"backwards.csv", "id,t,x,z\n1,5,0,0\n2,4,0,0\n", "t_s"},
      {"infinite.csv", "id,t,x,z\n1,0,0,inf\n", "z"},
      {"short-row.csv", "id,t,x,z\n1,0,0\n", "line 2: has 3 fields"},
  };
  for (const Case& c : cases) {
    const std::string path = dir / c.name;
    test::WriteText(path, c.text);
    test::ExpectRejected(path, c.expect, [&] { ReadVendorCsv(path, columns); });
  }
}

// The command line: import the real export, measure it (every row invalid,
// and the summary says the reference areas hold no points), and refuse a
// flow on it (no encoder readings), each with a message naming the file.
TEST(VendorCsv, CommandLineImportsMeasuresAndRefusesFlow) {
  test::TempDir dir;
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  auto run = [&](const std::string& args) { return test::RunCli(dir, args); };
  const std::string h5 = dir / "layer.h5";
  auto [imported, import_out] = run("import " + kReal + " -o " + h5 +
                                    " --profile-column ScanID --time-column Timestamp --x-column X --z-column Z"
                                    " --z-distance");
  ASSERT_EQ(imported, 0) << import_out;
  EXPECT_NE(import_out.find("12916 points in 399 profiles"), std::string::npos) << import_out;
  EXPECT_NE(import_out.find("no encoder column"), std::string::npos) << import_out;
  auto [measured, measure_out] = run("measure --rig " + (dir / "rig.yaml") + " " + h5 + " -o " + (dir / "g.csv"));
  ASSERT_EQ(measured, 0) << measure_out;
  EXPECT_NE(measure_out.find("399 profiles, 0 valid"), std::string::npos) << measure_out;
  EXPECT_NE(measure_out.find("no profile has enough points in the reference areas"), std::string::npos) << measure_out;
  auto [flowed, flow_out] = run("flow --rig " + (dir / "rig.yaml") + " " + h5 + " -o " + (dir / "f.csv"));
  EXPECT_EQ(flowed, 1) << flow_out;
  EXPECT_NE(flow_out.find(h5 + ": /profiles/encoder: holds no readings"), std::string::npos) << flow_out;
  EXPECT_FALSE(std::filesystem::exists(dir / "f.csv"));
}

}  // namespace
}  // namespace bead
