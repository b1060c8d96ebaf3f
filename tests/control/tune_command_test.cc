// `bead tune` on a model file: every method's row, the controller file,
// the closing line in the form scripts read, and the errors that say what
// to fix.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "libbead/control/closed_loop.h"
#include "libbead/sim/sim_writer.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

// Seed 004's eq. 14: 1.0033 / ((44.1315 s + 1)(2.0042 s + 1)(1.9689 s + 1)).
const char* kEq14 = R"({"num": [1.0033], "den": [174.14596084, 179.28493203, 48.1046, 1.0], "delay_s": 0.0})";

TEST(TuneCommand, ComparesEveryMethodAndWritesTheController) {
  test::TempDir dir;
  test::WriteText(dir / "m.json", kEq14);
  auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " --compare -o " + (dir / "c.yaml"));
  ASSERT_EQ(status, 0) << out;
  for (const char* m : {"max-stability", "simc", "imc", "zn", "cohen-coon"})
    EXPECT_NE(out.find(std::string("\n") + m + " "), std::string::npos) << m << "\n" << out;
  // The last line: the chosen (default) method's gains and J.
  const std::regex last(R"(kp=([0-9.e+-]+) ki=([0-9.e+-]+) kd=([0-9.e+-]+) stability_degree=([0-9.e+-]+)\n$)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, last)) << out;
  // Table I row 4 (kp 10.836, ki 0.7611, kd 21.032, J 0.26), to the
  // paper's digits; J to the fourfold root's split by 6-digit gains.
  EXPECT_NEAR(std::stod(m[1]), 10.836, 0.01 * 10.836);
  EXPECT_NEAR(std::stod(m[2]), 0.7611, 0.01 * 0.7611);
  EXPECT_NEAR(std::stod(m[3]), 21.032, 0.01 * 21.032);
  EXPECT_NEAR(std::stod(m[4]), 0.2574, 0.047 * 0.2574);
  const YAML::Node c = YAML::LoadFile(dir / "c.yaml");
  EXPECT_EQ(c["format"].as<std::string>(), "bead controller 1");
  EXPECT_EQ(c["method"].as<std::string>(), "max-stability");
  EXPECT_DOUBLE_EQ(c["pid"]["kp"].as<double>(), std::stod(m[1]));
  EXPECT_EQ(c["model"]["source"].as<std::string>(), dir / "m.json");
  EXPECT_GT(c["margins"]["phase_margin_deg"].as<double>(), 0);
  EXPECT_NEAR(c["stability_degree"].as<double>(), std::stod(m[4]), 1e-5);
}

TEST(TuneCommand, ErrorsSayWhatToFix) {
  test::TempDir dir;
  test::WriteText(dir / "m.json", kEq14);
  auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " --method pi");
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("max-stability, simc, imc, zn, cohen-coon"), std::string::npos) << out;
  // A second-order model has no maximum: the user is told to choose J.
  test::WriteText(dir / "two.json", R"({"num": [1.0031], "den": [98.0034816, 46.2302, 1.0]})");
  std::tie(status, out) = test::RunCli(dir, "tune " + (dir / "two.json") + " -o " + (dir / "c.yaml"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("--degree"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
  std::tie(status, out) = test::RunCli(dir, "tune " + (dir / "two.json") + " --degree 0.3");
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("kp=25.38"), std::string::npos) << out;
  test::WriteText(dir / "multi.json",
                  R"({"inputs": [{"num": [1], "den": [1, 1]}, {"num": [2], "den": [3, 1]}], "output": "q"})");
  std::tie(status, out) = test::RunCli(dir, "tune " + (dir / "multi.json"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("several inputs"), std::string::npos) << out;
}

// Thesis eq. 22 (screw RPM -> flow) has a direct feedthrough: as many zeros
// as poles. An ideal derivative on it makes the loop improper (with the
// delay, its quasi-polynomial is of advanced type: roots without bound in
// the right half plane); every design that uses one is refused, by name,
// and no file is written.
const char* const kMethods[] = {"max-stability", "simc", "imc", "zn", "cohen-coon"};
const char* kEq22 = R"({"num": [9.175, 149.2, 905.3], "den": [1, 12.84, 47.52], "delay_s": 0.15})";

TEST(TuneCommand, AModelWithFeedthroughGetsNoUnstableController) {
  test::TempDir dir;
  test::WriteText(dir / "m.json", kEq22);
  auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " --compare -o " + (dir / "c.yaml"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
  EXPECT_NE(out.find("no controller written"), std::string::npos) << out;
  EXPECT_NE(out.find("direct feedthrough"), std::string::npos) << out;
  // Every row that prints gains is followed by its verdict: no row with an
  // unstable loop goes unmarked.
  std::istringstream lines(out);
  std::string line, previous;
  int rows = 0;
  while (std::getline(lines, line)) {
    std::istringstream fields(previous);
    std::string method;
    double kp = 0;
    if (previous.rfind("method", 0) != 0 && (fields >> method >> kp) &&
        std::find(std::begin(kMethods), std::end(kMethods), method) != std::end(kMethods)) {
      ++rows;
      EXPECT_EQ(line.rfind("  ^ REFUSED", 0), 0u) << previous << "\n" << line;
    }
    previous = line;
  }
  EXPECT_GE(rows, 2) << out;
}

// A plant with a feedthrough (high-frequency gain 0.05) and a delay: with a
// derivative filter (or none: SIMC gives it a PI) the loop is well posed, and a design is written only
// when its margins hold. At the defaults (Ms <= 2, gain margin >= 1.5)
// SIMC's is refused for them; with the margins relaxed it is written, and
// its loop, simulated here from the file's gains, settles on the step.
TEST(TuneCommand, AFeedthroughWithAFilterIsWrittenOnlyWithinItsMargins) {
  test::TempDir dir;
  const char* model = R"({"num": [0.05, 1, 1], "den": [1, 2, 1], "delay_s": 0.1})";
  test::WriteText(dir / "m.json", model);
  const std::string base = "tune " + (dir / "m.json") + " --method simc --filter 2 -o " + (dir / "c.yaml");
  auto [status, out] = test::RunCli(dir, base);
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("peak sensitivity Ms"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
  std::tie(status, out) = test::RunCli(dir, base + " --max-ms 5 --min-gain-margin 1.2");
  ASSERT_EQ(status, 0) << out;
  const YAML::Node y = YAML::LoadFile(dir / "c.yaml");
  EXPECT_GT(y["stability_degree"].as<double>(), 0);
  EXPECT_LE(y["margins"]["ms"].as<double>(), 5.0);
  if (y["pid"]["kd"].as<double>() != 0) {
    EXPECT_GT(y["pid"]["derivative_filter_s"].as<double>(), 0);
  }
  const control::Pid pid{y["pid"]["kp"].as<double>(), y["pid"]["ki"].as<double>(), y["pid"]["kd"].as<double>(),
                         y["pid"]["derivative_filter_s"].as<double>()};
  // The loop from the file alone: L(inf) = g_inf kp (1 + N) below 1, and
  // the step settles to within 5 % (a stable loop's integral action).
  EXPECT_LT(0.05 * (pid.kp + (pid.tf_s > 0 ? pid.kd / pid.tf_s : 0.0)), 1.0);
  const model::TransferFunction g{{0.05, 1, 1}, {1, 2, 1}, 0.1};
  const control::StepFigures step = control::SetpointStep(g, pid, 60.0);
  EXPECT_NEAR(step.y.back(), 1.0, 0.05);
  EXPECT_TRUE(std::isfinite(step.settling_s));
}

// Option values are usage errors (exit 2); a J that cannot be met is said
// and refused (exit 1).
TEST(TuneCommand, OptionValuesAreCheckedAndAnUnmetDegreeIsSaid) {
  test::TempDir dir;
  test::WriteText(dir / "m.json", kEq14);
  for (const char* bad : {"--degree -1", "--degree 0", "--filter -5", "--filter 0", "--max-ms 0.5"}) {
    auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " " + bad);
    EXPECT_EQ(status, 2) << bad << "\n" << out;
  }
  for (const char* far : {"--degree 100", "--degree 1e9"}) {
    auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " " + far + " -o " + (dir / "c.yaml"));
    EXPECT_EQ(status, 1) << far << "\n" << out;
    EXPECT_NE(out.find("is not met"), std::string::npos) << far << "\n" << out;
    EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
  }
  // An output folder that does not exist is said before any design.
  auto [status, out] = test::RunCli(dir, "tune " + (dir / "m.json") + " -o " + (dir / "nodir/c.yaml"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("does not exist"), std::string::npos) << out;
  EXPECT_EQ(out.find("kp="), std::string::npos) << out;
}

}  // namespace
}  // namespace bead

namespace bead {
namespace {

// A plan of `ticks` 10-ms ticks stepping the extruder from 3 V to 4 V
// halfway, the thesis' flow model (eq. 22 with the twin's 0.15 s delay),
// and `bead feedforward` run on them into DIR/wheel.csv; its exit status
// and output.
std::pair<int, std::string> RunFeedforward(const test::TempDir& dir, int ticks) {
  test::WriteText(dir / "flow.json", R"({"num": [9.175, 149.2, 905.3], "den": [1, 12.84, 47.52], "delay_s": 0.15})");
  std::string plan = "t_s,extruder_cmd_v\n";
  for (int i = 0; i <= ticks; ++i) plan += std::to_string(0.01 * i) + "," + (i < ticks / 2 ? "3.0" : "4.0") + "\n";
  test::WriteText(dir / "plan.csv", plan);
  return test::RunCli(dir, "feedforward --plan " + (dir / "plan.csv") + " --flow-model " + (dir / "flow.json") +
                               " --thesis-rpm-model --thesis-wheel --target-area 14 -o " + (dir / "wheel.csv"));
}

// `bead feedforward`: a plan of extruder steps and the thesis' flow model
// (eq. 22, delay 0.15 s) give a wheel command CSV and the predicted
// variation beside a constant wheel's; a plan without the named column is
// refused by name.
TEST(FeedforwardCommand, WritesTheWheelCommandToPlay) {
  test::TempDir dir;
  auto [status, out] = RunFeedforward(dir, 1000);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("times less variation"), std::string::npos) << out;
  const std::string csv = test::ReadText(dir / "wheel.csv");
  EXPECT_EQ(
      csv.rfind("t_s,extruder_cmd_v,wheel_cmd_v,predicted_flow_mm3_s,predicted_speed_mm_s,predicted_area_mm2\n", 0),
      0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 1001);
  std::tie(status, out) = test::RunCli(
      dir, "feedforward --plan " + (dir / "plan.csv") + " --command volts --flow-model " + (dir / "flow.json") +
               " --thesis-rpm-model --thesis-wheel --target-area 14 -o " + (dir / "w2.csv"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("no column 'volts'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "w2.csv"));
}

// The rig's constants come from the user's files, the thesis rig's only by
// name: without an RPM model, a wheel model or a target the command
// refuses (usage, exit 2) naming the ways to give each; the same constants
// given as the user's files (models of the thesis' eq. 21 and 3.3.3 wheel,
// the rig's 254.762 mm wheel, a measured run whose median valid area is 14
// mm^2) give the same command as the thesis' by name.
TEST(FeedforwardCommand, TheRigsConstantsComeFromTheUsersFilesOrByName) {
  test::TempDir dir;
  auto [status, out] = RunFeedforward(dir, 400);
  ASSERT_EQ(status, 0) << out;
  const std::string base = "feedforward --plan " + (dir / "plan.csv") + " --flow-model " + (dir / "flow.json");
  std::tie(status, out) = test::RunCli(dir, base + " --target-area 14 --thesis-wheel -o " + (dir / "a.csv"));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--thesis-rpm-model"), std::string::npos) << out;
  std::tie(status, out) = test::RunCli(dir, base + " --target-area 14 --thesis-rpm-model -o " + (dir / "a.csv"));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--wheel-model WHEEL.json"), std::string::npos) << out;
  std::tie(status, out) = test::RunCli(dir, base + " --thesis-rpm-model --thesis-wheel -o " + (dir / "a.csv"));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--target-from"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "a.csv"));

  test::WriteText(dir / "rpm.json", R"({"num": [439.0, 35.08], "den": [1.523, 11.44, 1.0], "delay_s": 0.054})");
  test::WriteText(dir / "wheel.json", R"({"num": [2.517], "den": [0.0377, 1.0], "delay_s": 0.009})");
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  test::WriteText(dir / "flow.csv", "t_s,area_mm2,valid\n0,13,1\n1,14,1\n2,15,1\n3,100,0\n4,,1\n");
  std::tie(status, out) = test::RunCli(dir, base + " --rpm-model " + (dir / "rpm.json") + " --wheel-model " +
                                                (dir / "wheel.json") + " --rig " + (dir / "rig.yaml") +
                                                " --target-from " + (dir / "flow.csv") + " -o " + (dir / "mine.csv"));
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("target area: 14 mm^2"), std::string::npos) << out;
  EXPECT_EQ(test::ReadText(dir / "mine.csv"), test::ReadText(dir / "wheel.csv"));
  test::WriteText(dir / "two_poles.json", R"({"num": [1.0], "den": [1.0, 2.0, 1.0], "delay_s": 0})");
  std::tie(status, out) =
      test::RunCli(dir, base + " --thesis-rpm-model --wheel-model " + (dir / "two_poles.json") + " --rig " +
                            (dir / "rig.yaml") + " --target-area 14 -o " + (dir / "b.csv"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("one stable pole and no zero"), std::string::npos) << out;
}

// The played plan, as a user runs it: `bead feedforward` writes the wheel
// command, a simulation config names it (wheel.cmd_csv, beside the
// config), `bead simulate` plays it on the twin, and the laid bead holds
// the target area once the extruder's steps are under way.
TEST(FeedforwardCommand, TheTwinPlaysTheWheelCommand) {
  test::TempDir dir;
  // The twin's own extruder models: thesis eq. 21 (its default) and eq. 22.
  auto [status, out] = RunFeedforward(dir, 800);
  ASSERT_EQ(status, 0) << out;
  test::WriteText(dir / "twin.yaml",
                  "seed: 3\nduration_s: 8\nwarm_start: true\n"
                  "extruder: {command: {kind: steps, levels_v: [3.0, 4.0], durations_s: [4, 100], start_s: 0}}\n"
                  "wheel: {mode: commanded, cmd_csv: wheel.csv}\n");
  std::tie(status, out) = test::RunCli(dir, "simulate " + (dir / "twin.yaml") + " -o " + (dir / "run"));
  ASSERT_EQ(status, 0) << out;
  const sim::Truth truth = sim::ReadTruth(dir / "run/truth.h5");
  // The twin's flow carries 1 % of noise: the laid area within 5 % of the
  // target wherever a bead was measured after the first second.
  const auto& a = truth.profiles.area_true_mm2;
  std::size_t checked = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (truth.profiles.t_s[i] > 1.0 && a[i] > 0) {
      EXPECT_NEAR(a[i], 14.0, 0.05 * 14.0) << "t " << truth.profiles.t_s[i];
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
  // A command CSV without the column is refused by name.
  test::WriteText(dir / "bad.csv", "t_s,volts\n0,1\n");
  test::WriteText(dir / "bad.yaml", "wheel: {mode: commanded, cmd_csv: bad.csv}\n");
  std::tie(status, out) = test::RunCli(dir, "simulate " + (dir / "bad.yaml") + " -o " + (dir / "run2"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("wheel_cmd_v"), std::string::npos) << out;
}

}  // namespace
}  // namespace bead
