// The wheel's runout: a known once/twice-per-revolution height with drift
// and noise comes back within its intervals; on the twin, an eccentric
// wheel's eccentricity and phase are found from the reference line, and
// the flow corrected with them is as close to the truth as a centred
// wheel's.
#include "calibration/wheel_runout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <regex>

#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/flow/flow.h"
#include "libbead/profile/measure_block.h"
#include "libbead/series/encoder.h"
#include "libbead/series/interpolate.h"
#include "libbead/sim/rig_simulator.h"
#include "tests/support/run_cli.h"

namespace bead::calibration {
namespace {

Rig WheelRig() {
  Rig r;
  r.encoder.counts_per_rev = 4096;
  r.wheel_diameter_mm = 254.762;
  return r;
}

double AngleGap(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

// Five turns at 200 profiles a revolution: h = 0.8 cos(theta - 123 deg) +
// 0.1 cos(2 (theta - 40 deg)) + a 0.05 mm warm-up drift + white noise of
// 0.01 mm. The terms' intervals hold the truth (a 95 % interval: these
// are fixed seeds, so the check cannot be flaky), and are narrow: the
// noise over 1000 profiles gives se ~ 0.01 sqrt(2 / 1000) = 0.0004 mm.
TEST(WheelRunout, KnownTermsComeBackWithinTheirIntervals) {
  const Rig rig = WheelRig();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<double> t, counts, h;
  for (int k = 0; k < 1000; ++k) {
    t.push_back(0.01 * k);
    counts.push_back(1234.0 + k * 4096.0 / 200.0);
    const double th = 2 * M_PI * counts.back() / 4096.0;
    h.push_back(0.8 * std::cos(th - 123 * M_PI / 180) + 0.1 * std::cos(2 * (th - 40 * M_PI / 180)) +
                0.05 * (1 - std::exp(-t.back() / 3.0)) + noise(rng));
  }
  h[17] = NAN;  // a profile without a reference line is skipped
  const WheelRunout w = FitWheelRunout(rig, t, counts, h);
  EXPECT_EQ(w.profiles_used, 999);
  EXPECT_NEAR(w.turns, 999.0 / 200, 1e-9);
  EXPECT_NEAR(w.eccentricity_mm, 0.8, w.eccentricity_ci95_mm);
  EXPECT_LT(w.eccentricity_ci95_mm, 0.003);
  EXPECT_LT(AngleGap(w.phase_deg, 123.0), w.phase_ci95_deg);
  EXPECT_NEAR(w.twice_mm, 0.1, w.twice_ci95_mm);
  EXPECT_LT(AngleGap(w.twice_phase_deg, 40.0), 1.0);
  // Peak to peak of 0.8 cos(a) + 0.1 cos(2 (a - b)), b = 40 - 123 deg:
  // found by scanning, to the fit's own error.
  double lo = 1e9, hi = -1e9;
  for (int j = 0; j < 3600; ++j) {
    const double a = 2 * M_PI * j / 3600;
    const double v = 0.8 * std::cos(a) + 0.1 * std::cos(2 * (a - (40.0 - 123.0) * M_PI / 180));
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  EXPECT_NEAR(w.runout_mm, hi - lo, 3 * w.eccentricity_ci95_mm);
  EXPECT_NEAR(w.residual_rms_mm, 0.01, 0.002);
}

TEST(WheelRunout, LessThanATurnIsRefused) {
  const Rig rig = WheelRig();
  std::vector<double> t, counts, h;
  for (int k = 0; k < 100; ++k) t.push_back(k), counts.push_back(k * 30.0), h.push_back(0.0);
  try {
    FitWheelRunout(rig, t, counts, h);
    ADD_FAILURE() << "fitted under a turn";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0.72 of a turn"), std::string::npos) << e.what();
  }
}

struct TwinFlow {
  WheelRunout runout;  // of the reference line's height
  WheelRunout error;   // of the flow's relative error against the truth: its once-per-revolution part
  Rig rig;
};

// Runs the twin; flow with the rig file as given, or corrected with the
// eccentricity the run itself gives.
TwinFlow RunTwin(double eccentricity_mm, bool correct) {
  sim::SimConfig c;
  c.seed = 31;
  c.duration_s = 20.0;  // 15 RPM: five turns
  c.sensor.points = 160;
  c.sensor.runout_mm = 0.0;  // all the once-per-revolution height is the wheel's eccentricity
  c.effects.eccentricity_mm = eccentricity_mm;
  const sim::SimulatedRun s = sim::Simulate(c);
  const ProfileBlock& b = s.run.profiles;
  TwinFlow out;
  out.rig = s.rig_file;
  const std::vector<BeadGeometry> g = MeasureProfiles(b.size(), [&](std::size_t i) { return b.view(i); },
                                                      out.rig.reference_left, out.rig.reference_right, {});
  const EncoderTrack track = UnwrapEncoder(b.encoder, out.rig.encoder, b.t_s);
  std::vector<double> h(b.size(), NAN);
  for (std::size_t k = 0; k < b.size(); ++k)
    if (g[k].reference.ok) h[k] = g[k].reference.intercept_mm;
  out.runout = FitWheelRunout(out.rig, b.t_s, track.counts, h);
  if (correct) {
    out.rig.wheel_eccentricity_mm = out.runout.eccentricity_mm;
    out.rig.wheel_eccentricity_phase_deg = out.runout.phase_deg;
  }
  const FlowResult f = ComputeFlow(out.rig, b, g, *s.run.log);
  const auto& truth = s.truth.flow;
  std::vector<double> relative(b.size(), NAN);
  for (std::size_t k = 0; k < b.size(); ++k) {
    const FlowSample& x = f.samples[k];
    if (!x.valid) continue;
    const double q = InterpolateLinear(truth.t_s.data(), truth.flow_mm3_s.data(), truth.t_s.size(), x.t_s);
    if (q > 100.0) relative[k] = x.flow_mm3_s / q - 1.0;
  }
  // The same fit, on the error against the wheel's angle at the laser
  // (the material's footing): its once-per-revolution amplitude.
  out.error = FitWheelRunout(out.rig, b.t_s, track.counts, relative);
  return out;
}

// e = 2 mm on R = 127.4 mm: the surface speed under the nozzle is off by
// +-1.57 % once a revolution. The flow's relative error against the truth,
// fitted against the wheel's angle like the runout: the correction takes
// e / R out of its once-per-revolution amplitude (within the two fits'
// intervals). What is left is not the speed: the surface also comes 2 mm
// nearer and farther once a revolution, and the fan sensor's view of the
// bead (its occlusion, not corrected in this test) changes with it: about
// 0.006 here, a third of what the speed gave. The centred wheel shows
// none of either. The phase:
// the counter's angle where the point under the laser is highest,
// 360 (start + offset) / counts_per_rev (the twin's counter starts at
// start_count; the point under the laser stood under the nozzle `offset`
// counts before).
TEST(WheelRunout, TheTwinsEccentricWheelIsFoundAndItsFlowCorrected) {
  const TwinFlow centred = RunTwin(0.0, false), off = RunTwin(2.0, false), corrected = RunTwin(2.0, true);
  const sim::SimConfig defaults;
  EXPECT_NEAR(off.runout.eccentricity_mm, 2.0, std::max(off.runout.eccentricity_ci95_mm, 0.02));
  const double expected_phase =
      360.0 * (defaults.rig.encoder.direction * double(defaults.encoder.start_count) + defaults.rig.offset_counts) /
      defaults.rig.encoder.counts_per_rev;
  EXPECT_LT(AngleGap(off.runout.phase_deg, expected_phase), std::max(off.runout.phase_ci95_deg, 1.0));
  EXPECT_LT(centred.runout.eccentricity_mm, 3 * centred.runout.eccentricity_ci95_mm + 0.005);
  const double e_over_r = 2.0 / (0.5 * defaults.rig.wheel_diameter_mm);
  std::printf(
      "flow's once-per-revolution error: centred %.4f +- %.4f, eccentric %.4f +- %.4f, corrected %.4f +- "
      "%.4f (e / R = %.4f)\n",
      centred.error.eccentricity_mm, centred.error.eccentricity_ci95_mm, off.error.eccentricity_mm,
      off.error.eccentricity_ci95_mm, corrected.error.eccentricity_mm, corrected.error.eccentricity_ci95_mm, e_over_r);
  EXPECT_NEAR(off.error.eccentricity_mm - corrected.error.eccentricity_mm, e_over_r,
              off.error.eccentricity_ci95_mm + corrected.error.eccentricity_ci95_mm);
  EXPECT_LT(corrected.error.eccentricity_mm, 0.5 * off.error.eccentricity_mm);
  EXPECT_LT(centred.error.eccentricity_mm, 2 * centred.error.eccentricity_ci95_mm);
}

// The command end to end: the twin's run with an eccentric wheel, the
// table and the closing line, the rig file written with the new keys and
// read back by `bead flow`; a run under a turn is refused naming it.
TEST(WheelCommand, CalibratesWritesTheRigAndFlowUsesIt) {
  test::TempDir dir;
  test::WriteText(dir / "sim.yaml",
                  "seed: 5\nduration_s: 10\nsensor: {points: 160, runout_mm: 0}\neffects: {eccentricity_mm: 1.0}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  const std::string rig = dir / "twin/rig.yaml", run = dir / "twin/run.h5";
  auto [status, out] = test::RunCli(dir, "calibrate wheel --rig " + rig + " " + run + " -o " + (dir / "rig2.yaml"));
  ASSERT_EQ(status, 0) << out;
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(out, m, std::regex(R"(runout_mm=([0-9.]+) eccentricity_mm=([0-9.]+) phase_deg=([0-9.]+))")))
      << out;
  EXPECT_NEAR(std::stod(m[2]), 1.0, 0.05) << out;
  EXPECT_NE(out.find("over 2.5"), std::string::npos) << out;  // 10 s at 15 RPM
  const RigFile written = ReadRigFile(dir / "rig2.yaml");
  EXPECT_NEAR(written.rig.wheel_eccentricity_mm, std::stod(m[2]), 1e-4);
  EXPECT_NEAR(written.rig.wheel_eccentricity_phase_deg, std::stod(m[3]), 0.05);
  auto [flow, flow_out] =
      test::RunCli(dir, "flow --occlusion none --rig " + (dir / "rig2.yaml") + " " + run + " -o " + (dir / "flow.csv"));
  EXPECT_EQ(flow, 0) << flow_out;

  test::WriteText(dir / "short.yaml", "seed: 5\nduration_s: 2\nsensor: {points: 160}\n");
  ASSERT_EQ(test::RunCli(dir, "simulate " + (dir / "short.yaml") + " -o " + (dir / "short")).first, 0);
  auto [short_status, short_out] =
      test::RunCli(dir, "calibrate wheel --rig " + (dir / "short/rig.yaml") + " " + (dir / "short/run.h5"));
  EXPECT_EQ(short_status, 1) << short_out;
  EXPECT_NE(short_out.find("short/run.h5: the run covers 0."), std::string::npos) << short_out;
}

}  // namespace
}  // namespace bead::calibration
