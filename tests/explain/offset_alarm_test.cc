// The offset from the run on the runs a new user makes first, through the
// command as they run it (`bead simulate`, then `bead explain --pins`, the
// base model identified on the run's own flow): where the rig file's
// offset is the truth, the run never calls it OUTSIDE its interval and
// never says the pins DISAGREE. The shapes: the twin's sample run made
// 120 s long (the extruder stepped, the wheel steady, 400 points: the
// issue's false alarm, 3034.9 +- 7.2 against 3071.5), a minute of PRBS on
// a steady wheel and on a stepped one, at 128 and 400 points, and a wheel
// fed forward from the extruder. Where the wheel's speed barely changes
// the offset trades with the delay, and where it changes only in step with
// the extruder a position error is a change of the model's dynamics: the
// run must say it does not pin it.
//
// Then a rig file 77 counts short (the truth 3071.5, the file 2994.5),
// the base model identified on the flow it misaligns: on a stepped wheel
// the run's interval covers the truth and calls the file OUTSIDE (the
// model identified again on the flow aligned where the run says); on a
// fed-forward wheel the run pins nothing and the pins stand alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "libbead/series/interpolate.h"
#include "libbead/sim/sim_writer.h"

#include "tests/support/run_cli.h"

namespace bead {
namespace {

struct Shape {
  const char* name;
  std::string config;
  bool steady;  // the wheel's speed constant: the offset must be called not pinned
};

constexpr double kTrueOffset = 3071.5;  // the twin's rig (sim/sim_config.h)

std::string Prbs(int seed, int points, bool stepped_wheel, bool fed_forward = false, double rig_error = 0.0) {
  std::string c = "seed: " + std::to_string(seed) +
                  "\neffects: {rig_offset_error_counts: " + std::to_string(rig_error) + "}" +
                  "\nduration_s: 60\nwarm_start: true\nsensor: {points: " + std::to_string(points) +
                  "}\npins: {scans: 6}\nextruder:\n  command: {kind: prbs, base_v: 3.2, amplitude_v: 0.8, "
                  "bit_time_s: 0.5, start_s: 0.0}\n";
  if (stepped_wheel)
    c += "wheel: {mode: commanded, cmd_levels_v: [6.0, 4.5, 7.5, 6.0, 4.5, 7.5], cmd_durations_s: [10, 10, 10, 10, "
         "10, 10]}\n";
  if (fed_forward) c += "wheel: {mode: feedforward}\n";
  return c;
}

TEST(ExplainWarmRun, NoFalseOutsideOnRunsOfEveryShape) {
  const Shape shapes[] = {
      {"sample, 120 s, steady wheel, 400 points",
       "seed: 20261122\nduration_s: 120\nsensor: {points: 400}\npins: {scans: 6}\nextruder:\n  command: {kind: steps, "
       "levels_v: [3.0, 4.0, 2.5, 3.5], durations_s: [30, 30, 30, 30], start_s: 0.3}\n",
       true},
      {"PRBS, steady wheel, 128 points", Prbs(61, 128, false), true},
      {"PRBS, steady wheel, 400 points", Prbs(62, 400, false), true},
      {"PRBS, stepped wheel, 128 points", Prbs(63, 128, true), false},
      {"PRBS, stepped wheel, 400 points", Prbs(64, 400, true), false},
      {"PRBS, wheel fed forward from the extruder, 128 points", Prbs(65, 128, false, true), true},
  };
  int outside = 0;
  for (const Shape& s : shapes) {
    test::TempDir dir;
    test::WriteText(dir / "sim.yaml", s.config);
    auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
    ASSERT_EQ(sim, 0) << sim_out;
    const std::string twin = dir / "twin";
    auto [status, out] = test::RunCli(dir, "explain --rig " + twin + "/rig.yaml " + twin + "/run.h5 --pins " + twin +
                                               "/pins.h5 -o " + (dir / "e.json"));
    ASSERT_EQ(status, 0) << s.name << "\n" << out;
    const auto line = out.find("encoder offset from the run:");
    ASSERT_NE(line, std::string::npos) << out;
    std::printf("%s: %s\n", s.name, out.substr(line, out.find('\n', line) - line).c_str());
    outside += out.find("OUTSIDE") != std::string::npos || out.find("DISAGREE") != std::string::npos;
    EXPECT_EQ(out.find("OUTSIDE"), std::string::npos) << s.name << "\n" << out;
    EXPECT_EQ(out.find("DISAGREE"), std::string::npos) << s.name << "\n" << out;
    if (s.steady) {
      EXPECT_NE(out.find("NOT pinned"), std::string::npos) << s.name << "\n" << out;
    }
  }
  std::printf("false OUTSIDE or DISAGREE: %d of %zu runs\n", outside, std::size(shapes));
}

// simulate, then explain --pins; the terminal's text and the JSON.
struct Explained {
  std::string out;
  nlohmann::json j;
};
Explained SimulateAndExplain(const test::TempDir& dir, const std::string& config, const std::string& more = "") {
  test::WriteText(dir / "sim.yaml", config);
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  EXPECT_EQ(sim, 0) << sim_out;
  const std::string twin = dir / "twin";
  auto [status, out] = test::RunCli(dir, "explain --rig " + twin + "/rig.yaml " + twin + "/run.h5 --pins " + twin +
                                             "/pins.h5 -o " + (dir / "e.json") + more);
  EXPECT_EQ(status, 0) << out;
  return {out, status == 0 ? nlohmann::json::parse(test::ReadText(dir / "e.json")) : nlohmann::json{}};
}

// A flow CSV's RMS error against the twin's true flow (in extrusion time)
// over its valid rows.
double RmsAgainstTruth(const std::string& csv, const sim::Truth& truth) {
  std::istringstream in(test::ReadText(csv));
  std::string line;
  std::getline(in, line);  // the header: t_s first, flow_mm3_s sixth, valid ninth
  double sum = 0.0;
  int n = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
    if (f.size() < 9 || f[8] != "1") continue;
    const double t = std::stod(f[0]), q = std::stod(f[5]);
    const double e = q - InterpolateLinear(truth.flow.t_s, truth.flow.flow_mm3_s, t);
    sum += e * e, ++n;
  }
  return n ? std::sqrt(sum / n) : INFINITY;
}

TEST(ExplainWarmRun, StaleRigFileOnASteppedWheelIsCalledWithTheTruthCovered) {
  test::TempDir dir;
  const Explained e =
      SimulateAndExplain(dir, Prbs(102, 400, true, false, -77.0), " --flow-out " + (dir / "corrected.csv"));
  ASSERT_TRUE(e.j.contains("offset_profile")) << e.out;
  const double lo = e.j["offset_profile"]["ci95_low_counts"], hi = e.j["offset_profile"]["ci95_high_counts"];
  std::printf("stale rig file, stepped wheel: run %.1f [%.1f, %.1f], truth %.1f\n",
              e.j["offset_from_run_counts"].get<double>(), lo, hi, kTrueOffset);
  EXPECT_TRUE(e.j["offset_from_run_pinned"].get<bool>()) << e.out;
  EXPECT_LE(lo, kTrueOffset) << e.out;
  EXPECT_GE(hi, kTrueOffset) << e.out;
  EXPECT_NE(e.out.find("OUTSIDE"), std::string::npos) << e.out;
  EXPECT_NE(e.out.find("identified again"), std::string::npos) << e.out;
  EXPECT_EQ(e.out.find("DISAGREE"), std::string::npos) << e.out;
  // The corrected flow is the user's flow with the offset undone: written,
  // and nearer the truth than the flow the rig file aligns.
  const std::string twin = dir / "twin";
  auto [status, out] =
      test::RunCli(dir, "flow --rig " + twin + "/rig.yaml " + twin + "/run.h5 -o " + (dir / "as_filed.csv"));
  ASSERT_EQ(status, 0) << out;
  ASSERT_TRUE(std::filesystem::exists(dir / "corrected.csv")) << e.out;
  const sim::Truth truth = sim::ReadTruth(twin + "/truth.h5");
  const double before = RmsAgainstTruth(dir / "as_filed.csv", truth);
  const double after = RmsAgainstTruth(dir / "corrected.csv", truth);
  std::printf("flow against the truth: RMS %.2f mm^3/s as filed, %.2f corrected\n", before, after);
  EXPECT_LT(after, before);
}

TEST(ExplainWarmRun, StaleRigFileOnAFedForwardWheelLeavesThePinsAlone) {
  test::TempDir dir;
  const Explained e = SimulateAndExplain(dir, Prbs(72, 128, false, true, -77.0));
  EXPECT_NE(e.out.find("NOT pinned by this run: the wheel's speed follows the extruder"), std::string::npos) << e.out;
  EXPECT_NE(e.out.find("stands alone"), std::string::npos) << e.out;
  EXPECT_EQ(e.out.find("OUTSIDE"), std::string::npos) << e.out;
  ASSERT_TRUE(e.j.contains("pin_offset_counts")) << e.out;
  EXPECT_NEAR(e.j["pin_offset_counts"].get<double>(), kTrueOffset, e.j["pin_offset_ci95_counts"].get<double>());
}

// Every interval the run prints covers its truth, over stepped-wheel PRBS
// runs of both resolutions with the rig file right and 77 counts short
// (the model identified on the run's flow, as a new user runs it): at
// least 90 % of them covered, a right rig file never called OUTSIDE, and
// the stale file called OUTSIDE in at least 90 % of the stale runs pinned
// (its 77 counts are three half-widths and more: on 52 such runs the mean
// half-width was 10-22 counts, docs/explain.md). Each pinned run's JSON
// carries the profile with the model identified again at every trial
// offset, and its interval lies within the one printed. (At 128 points the
// intervals run about 1.7 times the spread of the estimates: the upper end
// of the 90-98 % band is not asserted here; IntervalCoverage
// asserts both ends where the truths are the model's.)
TEST(ExplainWarmRun, EveryPrintedOffsetIntervalCoversTheTruthOverTwelveRuns) {
  struct Run {
    int seed, points;
    double error;
  };
  std::vector<Run> runs;
  for (int k = 0; k < 12; ++k) runs.push_back({201 + k, k % 2 ? 400 : 128, (k / 2) % 2 ? -77.0 : 0.0});
  // Two at a time (the command runs on every core, but mostly on one).
  std::vector<test::TempDir> dirs(runs.size());
  std::vector<Explained> done(runs.size());
  for (std::size_t k = 0; k < runs.size(); k += 2) {
    std::vector<std::future<Explained>> pair;
    for (std::size_t j = k; j < std::min(k + 2, runs.size()); ++j)
      pair.push_back(std::async(std::launch::async, [&, j] {
        return SimulateAndExplain(dirs[j], Prbs(runs[j].seed, runs[j].points, true, false, runs[j].error));
      }));
    for (std::size_t j = 0; j < pair.size(); ++j) done[k + j] = pair[j].get();
  }
  int pinned = 0, covered = 0, false_outside = 0, stale_pinned = 0, stale_called = 0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const Explained& e = done[k];
    ASSERT_TRUE(e.j.contains("offset_profile")) << e.out;
    const bool pin = e.j["offset_from_run_pinned"].get<bool>();
    const double lo = e.j["offset_profile"]["ci95_low_counts"], hi = e.j["offset_profile"]["ci95_high_counts"];
    pinned += pin;
    covered += pin && lo <= kTrueOffset && kTrueOffset <= hi;
    false_outside += runs[k].error == 0.0 && e.out.find("OUTSIDE") != std::string::npos;
    stale_pinned += pin && runs[k].error != 0.0;
    stale_called += pin && runs[k].error != 0.0 && e.out.find("OUTSIDE") != std::string::npos;
    if (pin) {
      ASSERT_TRUE(e.j.contains("offset_profile_reidentified")) << e.out;
      const auto& r = e.j["offset_profile_reidentified"];
      EXPECT_GE(r["offset_counts"].size(), 5u);
      EXPECT_GE(r["ci95_low_counts"].get<double>(), lo - 1e-6);
      EXPECT_LE(r["ci95_high_counts"].get<double>(), hi + 1e-6);
    }
    std::printf("seed %d, %d points, rig file %+.0f: %s [%.1f, %.1f]\n", runs[k].seed, runs[k].points, runs[k].error,
                pin ? "pinned" : "not pinned", lo, hi);
  }
  std::printf("pinned %d of %zu, covering the truth %d; right rig file OUTSIDE %d; stale file OUTSIDE %d of %d\n",
              pinned, runs.size(), covered, false_outside, stale_called, stale_pinned);
  EXPECT_GE(pinned, 10) << "a stepped wheel pins the offset";
  EXPECT_GE(covered, static_cast<int>(std::ceil(0.9 * pinned)));
  EXPECT_EQ(false_outside, 0);
  EXPECT_GE(stale_called, static_cast<int>(std::ceil(0.9 * stale_pinned)));
}

}  // namespace
}  // namespace bead
