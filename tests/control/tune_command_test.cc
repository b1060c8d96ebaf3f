// `bead tune` on a model file: every method's row, the controller file,
// the closing line in the form scripts read, and the errors that say what
// to fix.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <regex>

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
                               " --target-area 14 -o " + (dir / "wheel.csv"));
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
  std::tie(status, out) =
      test::RunCli(dir, "feedforward --plan " + (dir / "plan.csv") + " --command volts --flow-model " +
                            (dir / "flow.json") + " -o " + (dir / "w2.csv"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("no column 'volts'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "w2.csv"));
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
