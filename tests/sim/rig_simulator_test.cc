// The digital twin against its own physics.
#include "libbead/sim/part_twin_io.h"
#include "libbead/sim/rig_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numeric>

#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/sim/sim_writer.h"
#include "tests/support/temp_dir.h"

namespace bead::sim {
namespace {

SimConfig Short(double seconds = 6.0) {
  SimConfig c;
  c.duration_s = seconds;
  c.sensor.points = 320;
  return c;
}

// The bead that passes the laser is the material the flow laid: summing
// area x surface travel over the profiles gives the integral of Q over the
// extrusion times they cover. Discretisation: profiles every 5 ms, the
// flow smooth on that scale (poles at -6.4 +- 2.5i /s), so 1e-3 relative.
TEST(RigSimulator, VolumePastTheLaserIsTheIntegralOfFlow) {
  SimConfig c = Short(8.0);
  c.extruder.command.kind = CommandConfig::Kind::kSteps;
  const SimulatedRun run = Simulate(c);
  const Truth& t = run.truth;
  const double v = c.wheel.surface_speed_mm_s;
  double volume_profiles = 0.0, first = NAN, last = NAN;
  for (std::size_t k = 0; k < t.profiles.t_s.size(); ++k) {
    if (std::isnan(t.profiles.t_extruded_s[k])) continue;
    volume_profiles += t.profiles.area_true_mm2[k] * v / c.sensor.rate_hz;
    if (std::isnan(first)) first = t.profiles.t_extruded_s[k];
    last = t.profiles.t_extruded_s[k];
  }
  double volume_flow = 0.0;
  for (std::size_t j = 1; j < t.flow.t_s.size(); ++j) {
    const double a = t.flow.t_s[j - 1], b = t.flow.t_s[j];
    if (a >= first && b <= last + 1.0 / c.sensor.rate_hz)
      volume_flow += 0.5 * (t.flow.flow_mm3_s[j] + t.flow.flow_mm3_s[j - 1]) * (b - a);
  }
  ASSERT_GT(volume_flow, 1000.0);
  EXPECT_NEAR(volume_profiles / volume_flow, 1.0, 1e-3);
  // And the whole run's volume is the integral of its flow.
  double total = 0.0;
  for (std::size_t j = 1; j < t.flow.t_s.size(); ++j)
    total += 0.5 * (t.flow.flow_mm3_s[j] + t.flow.flow_mm3_s[j - 1]) * (t.flow.t_s[j] - t.flow.t_s[j - 1]);
  EXPECT_NEAR(total / t.total_volume_mm3, 1.0, 1e-3);
}

// Area laid = Q / v at the nozzle; the laser sees it offset counts later:
// t_measured - t_extruded = offset distance / surface speed.
TEST(RigSimulator, MaterialReachesTheLaserOffsetLater) {
  const SimConfig c = Short();
  const SimulatedRun run = Simulate(c);
  const double travel_s = c.rig.offset_counts * c.rig.MmPerCount() / c.wheel.surface_speed_mm_s;
  int checked = 0;
  for (std::size_t k = 0; k < run.truth.profiles.t_s.size(); ++k) {
    if (std::isnan(run.truth.profiles.t_extruded_s[k])) continue;
    EXPECT_NEAR(run.truth.profiles.t_s[k] - run.truth.profiles.t_extruded_s[k], travel_s, 1e-6);
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

// Seen straight above (no fan, no roll), a bead without undercut has
// visible area equal to its true area; with undercut, more.
TEST(RigSimulator, NoUndercutStraightAboveVisibleEqualsTrue) {
  SimConfig c = Short(5.0);  // the default command holds 0 V for the first second
  c.bead.shape = BeadConfig::Shape::kParabola;
  c.sensor.fan = false;
  c.sensor.roll_deg = 0.0;
  const SimulatedRun run = Simulate(c);
  int beads = 0;
  for (std::size_t k = 0; k < run.truth.profiles.t_s.size(); ++k) {
    const double a = run.truth.profiles.area_true_mm2[k];
    if (a <= 0) continue;
    EXPECT_NEAR(run.truth.profiles.area_visible_mm2[k], a, 1e-9 * a);
    ++beads;
  }
  EXPECT_GT(beads, 300);
  c.bead.shape = BeadConfig::Shape::kRoundedRectangle;
  const SimulatedRun undercut = Simulate(c);
  const auto& p = undercut.truth.profiles;
  for (std::size_t k = 0; k < p.t_s.size(); ++k)
    if (p.area_true_mm2[k] > 0) {
      EXPECT_GT(p.area_visible_mm2[k], p.area_true_mm2[k] * 1.01);
    }
}

// The pin's widest chord crosses the laser where the offset puts it: the
// travel from placement is offset - placement error, in counts.
TEST(RigSimulator, PinPeakIsWhereTheOffsetPutsIt) {
  SimConfig c = Short(1.0);
  c.sensor.fan = false;
  c.sensor.z_sigma_mm = 0.0;
  c.sensor.dropout_prob = 0.0;
  c.sensor.spike_prob = 0.0;
  c.sensor.dropped_profile_prob = 0.0;
  const SimulatedRun run = Simulate(c);
  ASSERT_EQ(run.pins.scans.size(), 6u);
  const double mpc = c.rig.MmPerCount();
  for (std::size_t k = 0; k < run.pins.scans.size(); ++k) {
    const ProfileBlock& b = run.pins.scans[k].profiles;
    // The pin is in the laser plane while |travel - meet| < r: its centre
    // is midway between the first and the last profile that sees it.
    long first = -1, last = -1;
    for (std::size_t i = 0; i < b.size(); ++i) {
      bool seen = false;
      for (std::size_t j = 0; j < b.points; ++j) seen = seen || b.z_mm[i * b.points + j] > c.pins.height_mm / 2;
      if (seen && first < 0) first = static_cast<long>(i);
      if (seen) last = static_cast<long>(i);
    }
    ASSERT_GE(first, 0);
    const double start = static_cast<double>(run.pins.scans[k].start_encoder);
    const double counts = 0.5 * (static_cast<double>(b.encoder[first]) + static_cast<double>(b.encoder[last])) - start;
    EXPECT_NEAR(run.truth.pins.peak_counts[k], c.rig.offset_counts - run.truth.pins.placement_error_mm[k] / mpc, 1e-9);
    // Entry and exit are each located to one scan step; the counter floors
    // to whole counts (up to one count below the wheel's position).
    const double step_counts = c.pins.scan_speed_mm_s / c.sensor.rate_hz / mpc;
    EXPECT_NEAR(counts, run.truth.pins.peak_counts[k], step_counts + 1.0) << "scan " << k;
  }
}

TEST(RigSimulator, EncoderWrapsAndRunsBackward) {
  SimConfig c = Short(2.0);
  c.rig.encoder.bits = 12;
  c.rig.encoder.direction = -1;
  const SimulatedRun run = Simulate(c);
  const auto& e = run.run.log->encoder;
  int wraps = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    ASSERT_GE(e[i], 0);
    ASSERT_LT(e[i], 4096);
    if (i > 0 && e[i] > e[i - 1]) ++wraps;  // counting down, a rise is a wrap
  }
  // 2 s at 200 mm/s over 0.039 mm per count: ~10,200 counts, two and a half turns of a 12-bit counter.
  EXPECT_GE(wraps, 2);
  EXPECT_LE(wraps, 3);
}

TEST(RigSimulator, EffectsChangeWhatTheyShould) {
  SimConfig c = Short(4.0);
  c.effects.rig_offset_error_counts = 25.0;
  c.effects.shrink_frac = 0.04;
  c.effects.shrink_tau_s = 0.05;
  const SimulatedRun run = Simulate(c);
  EXPECT_DOUBLE_EQ(run.rig_file.offset_counts, c.rig.offset_counts + 25.0);
  EXPECT_DOUBLE_EQ(run.truth.offset_counts, c.rig.offset_counts);
  // Shrinkage: at the laser the area is the laid area times 1 - 0.04 (1 - exp(-dt / tau)).
  const SimulatedRun plain = Simulate(Short(4.0));
  const double dt = c.rig.offset_counts * c.rig.MmPerCount() / c.wheel.surface_speed_mm_s;
  const double factor = 1 - 0.04 * (1 - std::exp(-dt / 0.05));
  const auto& a = run.truth.profiles.area_true_mm2;
  const auto& b = plain.truth.profiles.area_true_mm2;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (b[k] > 0) {
      EXPECT_NEAR(a[k] / b[k], factor, 1e-9);
    }
}

TEST(RigSimulator, SameSeedSameBytesOtherSeedOtherNoise) {
  test::TempDir dir;
  SimConfig c = Short(1.0);
  WriteSimulatedRun(dir / "a", Simulate(c));
  WriteSimulatedRun(dir / "b", Simulate(c));
  for (const char* f : {"run.h5", "pins.h5", "rig.yaml", "truth.h5"})
    EXPECT_EQ(test::ReadText(dir / (std::string("a/") + f)), test::ReadText(dir / (std::string("b/") + f))) << f;
  c.seed = 2;
  WriteSimulatedRun(dir / "c", Simulate(c));
  EXPECT_NE(test::ReadText(dir / "a/run.h5"), test::ReadText(dir / "c/run.h5"));
  // The files it wrote are what the spec says: readable by our readers.
  const RunArchive back = ReadRunArchive(dir / "a/run.h5");
  EXPECT_EQ(back.profiles.size(), 201u);
  EXPECT_EQ(ReadRig(dir / "a/rig.yaml").offset_counts, c.rig.offset_counts);
  EXPECT_EQ(ReadTruth(dir / "a/truth.h5").profiles.t_s.size(), 201u);
}

TEST(SimConfig, ErrorsNameTheKeyAndLine) {
  EXPECT_NO_THROW(ParseSimConfig("seed: 3\nbead: {shape: superellipse}\n", "c.yaml"));
  try {
    ParseSimConfig("seed: 3\nbead:\n  shape: blob\n", "c.yaml");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("c.yaml: line 3: bead.shape: is 'blob', expected one of"), std::string::npos)
        << e.what();
  }
  try {
    ParseSimConfig("sensor:\n  rate_hz: -5\n", "c.yaml");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 2: sensor.rate_hz: must be a finite number in [1, 100000]"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ParseSimConfig("sensr: {}\n", "c.yaml"), Error);
  EXPECT_THROW(ParseSimConfig("extruder: {voltage_to_rpm: {num: [1, 2, 3], den: [1, 1]}}\n", "c.yaml"), Error);
}

}  // namespace
}  // namespace bead::sim

namespace bead::sim {
namespace {

// testdata/sample is generated, never edited: it regenerates bit for bit.
TEST(BundledSample, RegeneratesBitForBitFromItsConfig) {
  test::TempDir dir;
  const std::string source = BEAD_SOURCE_DIR;
  WriteSimulatedRun(dir / "sample", Simulate(ReadSimConfig(source + "/testdata/configs/sample.yaml")));
  for (const char* f : {"run.h5", "pins.h5", "rig.yaml", "truth.h5"})
    EXPECT_TRUE(test::ReadText(dir / (std::string("sample/") + f)) == test::ReadText(source + "/testdata/sample/" + f))
        << f << " differs: regenerate with bead simulate testdata/configs/sample.yaml -o testdata/sample";
}

}  // namespace
}  // namespace bead::sim

namespace bead::sim {
namespace {

// Every config in testdata/configs parses and simulates (shortened to 2 s;
// a part twin's to two layers of 10 mm: a profile every profile_spacing_mm
// of each layer's path, a contour's its perimeter; a layer of roads is one
// layer).
TEST(BundledConfigs, AllParseAndRun) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(BEAD_SOURCE_DIR) + "/testdata/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    if (std::optional<PartTwinConfig> part = ReadPartTwinConfig(entry.path().string())) {
      part->layers = part->roads > 1 ? 1 : 2;
      part->length_mm = 10.0;
      const PartTwin twin = SimulatePartWall(*part);
      const double per_layer = twin.path_length_mm / part->profile_spacing_mm;
      EXPECT_GE(static_cast<double>(twin.scan.profiles.size()), part->layers * (per_layer - 1.0)) << entry.path();
      continue;
    }
    SimConfig c = ReadSimConfig(entry.path().string());
    c.duration_s = std::min(c.duration_s, 2.0);
    const SimulatedRun run = Simulate(c);
    EXPECT_GT(run.run.profiles.size(), 300u) << entry.path();
    EXPECT_GT(run.truth.total_volume_mm3, 0.0) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 6);
}

}  // namespace
}  // namespace bead::sim
