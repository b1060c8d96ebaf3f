// `bead explain` as a user runs it: the bundled sample run (run mode) and
// a weld-style CSV (uneven, with gaps) validated on a second run; its JSON
// holds the fields the issue names; bad input fails with the file named.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

#include "libbead/explain/model_series.h"
#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"
#include "tests/support/temp_dir.h"

namespace bead::explain {
namespace {

int RunCli(const std::string& args, const std::string& out) {
  return std::system((std::string(BEAD_CLI) + " " + args + " > " + out + " 2>&1").c_str());
}

TEST(ExplainCommand, SampleRunReportsOffsetDiagnosticsAndSpectrum) {
  test::TempDir dir;
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample";
  // The thesis' flow model's form (eq. 22: two poles, two zeros).
  ASSERT_EQ(RunCli("explain --rig " + sample + "/rig.yaml " + sample + "/run.h5 --poles 2 --zeros 2 -o " +
                       (dir / "explain.json"),
                   dir / "out.txt"),
            0)
      << test::ReadText(dir / "out.txt");
  const std::string out = test::ReadText(dir / "out.txt");
  EXPECT_NE(out.find("encoder offset from the run"), std::string::npos) << out;
  const auto j = nlohmann::json::parse(test::ReadText(dir / "explain.json"));
  for (const char* key : {"effects_added", "unexplained", "offset_from_run_counts", "offset_from_run_ci95_counts",
                          "rig_offset_counts", "diagnostics", "spectrum", "fit_before_pct", "fit_after_pct"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["rig_offset_counts"].get<double>(), 3071.5);
  // The sample's rig file is the twin's truth: the run's interval covers
  // it. The sample's wheel turns at one speed for 12 s, where an offset is
  // a delay: the run does not pin it, and says so (no half-width).
  EXPECT_LE(j["offset_profile"]["ci95_low_counts"].get<double>(), 3071.5);
  EXPECT_GE(j["offset_profile"]["ci95_high_counts"].get<double>(), 3071.5);
  EXPECT_FALSE(j["offset_from_run_pinned"].get<bool>());
  // Said from the wheel's speed, whichever of two delays that fit alike
  // identify took (the joint fit's correlation depends on that).
  EXPECT_TRUE(j["offset_profile"]["steady_wheel"].get<bool>());
  EXPECT_TRUE(j["offset_from_run_ci95_counts"].is_null());
  EXPECT_NE(out.find("NOT pinned by this run"), std::string::npos) << out;
  EXPECT_TRUE(j["diagnostics"]["whiteness_before"].contains("chi2"));
  EXPECT_FALSE(j["spectrum"]["before"]["frequency_hz"].empty());
  // The default order (two poles, one zero, as identify's): whatever the
  // run says of the offset, its interval holds the truth and no alarm is
  // raised against the right rig file and pins.
  ASSERT_EQ(RunCli("explain --rig " + sample + "/rig.yaml " + sample + "/run.h5 --pins " + sample + "/pins.h5 -o " +
                       (dir / "default.json"),
                   dir / "default.txt"),
            0)
      << test::ReadText(dir / "default.txt");
  const std::string said = test::ReadText(dir / "default.txt");
  const auto d = nlohmann::json::parse(test::ReadText(dir / "default.json"));
  EXPECT_LE(d["offset_profile"]["ci95_low_counts"].get<double>(), 3071.5) << said;
  EXPECT_GE(d["offset_profile"]["ci95_high_counts"].get<double>(), 3071.5) << said;
  EXPECT_EQ(said.find("OUTSIDE"), std::string::npos) << said;
  EXPECT_EQ(said.find("DISAGREE"), std::string::npos) << said;
}

// Width of a weld bead against wire feed speed: sampled unevenly, off for a
// while in the middle, and drifting (heat); a second run drifts the same way.
// Two more columns: a torch temperature (a 9 s square wave, 20-30 C) that
// widens the bead by width_per_c per degree through a 1 s lag, and a fan's
// speed that acts on nothing.
void WriteWeldCsv(const std::string& path, unsigned seed, double width_per_c = 0.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> step(0.03, 0.07), level(4.0, 9.0), hold(0.5, 2.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<double> t, u;
  double next = 0.0, value = 6.0;
  for (double x = 0.0; x < 50.0; x += step(rng)) {
    if (x > 20.0 && x < 24.0) continue;
    if (x >= next) value = level(rng), next = x + hold(rng);
    t.push_back(x);
    u.push_back(value);
  }
  const std::vector<double> base = model::Predict({{0.5}, {0.3, 1.0}, 0.1}, 0.0, t, u, {},
                                                  FindProcessOn(t, u, std::vector<double>(t.size(), 1.0)).segments);
  std::mt19937_64 fan_rng(seed + 100);
  std::normal_distribution<double> fan(1200.0, 30.0);
  std::string csv = "time_s,wire_feed_m_min,width_mm,operator,torch_temp_c,fan_rpm\n";
  double lagged = 25.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double temp = std::fmod(t[i], 9.0) < 4.5 ? 30.0 : 20.0;
    if (i > 0) lagged += (1 - std::exp(-(t[i] - t[i - 1]) / 1.0)) * (temp - lagged);
    const double width = base[i] * (1 + width_per_c * (lagged - 25.0)) + 0.25 * (t[i] - 25.0) / 25.0 + noise(rng);
    csv += std::to_string(t[i]) + "," + std::to_string(u[i]) + "," + (i % 50 == 7 ? "" : std::to_string(width)) +
           ",anna," + std::to_string(temp) + "," + std::to_string(fan(fan_rng)) + "\n";
  }
  test::WriteText(path, csv);
}

TEST(ExplainCommand, AnyCsvWithAnotherRunAsHeldOutData) {
  test::TempDir dir;
  WriteWeldCsv(dir / "weld1.csv", 1);
  WriteWeldCsv(dir / "weld2.csv", 2);
  ASSERT_EQ(RunCli("explain " + (dir / "weld1.csv") + " --time time_s --input wire_feed_m_min --output width_mm " +
                       "--poles 1 --zeros 0 --validate " + (dir / "weld2.csv") + " -o " + (dir / "explain.json"),
                   dir / "out.txt"),
            0)
      << test::ReadText(dir / "out.txt");
  const auto j = nlohmann::json::parse(test::ReadText(dir / "explain.json"));
  ASSERT_FALSE(j["effects_added"].empty()) << test::ReadText(dir / "out.txt");
  EXPECT_EQ(j["effects_added"][0]["name"], "drift");
  EXPECT_LT(j["effects_added"][0]["rms_after"].get<double>(), j["effects_added"][0]["rms_before"].get<double>());
  EXPECT_TRUE(j["offset_from_run_counts"].is_null());
}

// Columns named with --channels are tried as causes: the torch temperature
// that widens the bead is found with its lag and gain, the fan is not.
TEST(ExplainCommand, CsvChannelsNamedAreTriedAsCauses) {
  test::TempDir dir;
  WriteWeldCsv(dir / "weld.csv", 4, 0.04);
  ASSERT_EQ(RunCli("explain " + (dir / "weld.csv") + " --time time_s --input wire_feed_m_min --output width_mm " +
                       "--poles 1 --zeros 0 --channels torch_temp_c,fan_rpm -o " + (dir / "explain.json"),
                   dir / "out.txt"),
            0)
      << test::ReadText(dir / "out.txt");
  const auto j = nlohmann::json::parse(test::ReadText(dir / "explain.json"));
  bool torch = false;
  for (const auto& e : j["effects_added"]) {
    EXPECT_NE(e["name"], "channel[fan_rpm]") << test::ReadText(dir / "out.txt");
    if (e["name"] != "channel[torch_temp_c]") continue;
    torch = true;
    // The lag is the channel's own; the gain is relative to a base model
    // identified on this same run, whose own gain took part of the effect.
    const auto& lag = e["parameters"]["lag_s"];
    EXPECT_NEAR(lag["value"].get<double>(), 1.0, 1.5 * lag["ci95"].get<double>()) << test::ReadText(dir / "out.txt");
    EXPECT_GT(e["parameters"]["rel_per_unit"]["value"].get<double>(), 0.5 * 0.04);
    EXPECT_LT(e["parameters"]["rel_per_unit"]["value"].get<double>(), 1.5 * 0.04);
  }
  EXPECT_TRUE(torch) << test::ReadText(dir / "out.txt");
  // A column that is not there is named with the file's columns.
  EXPECT_NE(RunCli("explain " + (dir / "weld.csv") + " --time time_s --input wire_feed_m_min --output width_mm " +
                       "--channels nozzle_temp -o " + (dir / "e.json"),
                   dir / "out.txt"),
            0);
  EXPECT_NE(test::ReadText(dir / "out.txt").find("no column 'nozzle_temp'"), std::string::npos);
}

TEST(ExplainCommand, BadInputNamesTheFile) {
  test::TempDir dir;
  WriteWeldCsv(dir / "weld.csv", 3);
  EXPECT_NE(RunCli("explain " + (dir / "weld.csv") + " --input nope --output width_mm -o " + (dir / "e.json"),
                   dir / "out.txt"),
            0);
  std::string out = test::ReadText(dir / "out.txt");
  EXPECT_NE(out.find("weld.csv"), std::string::npos) << out;
  EXPECT_NE(out.find("no column 'nope'"), std::string::npos) << out;
  test::WriteText(dir / "model.json", "{\"num\": [1.0]}");
  EXPECT_NE(
      RunCli("explain " + (dir / "weld.csv") + " --time time_s --input wire_feed_m_min --output width_mm --model " +
                 (dir / "model.json") + " -o " + (dir / "e.json"),
             dir / "out.txt"),
      0);
  out = test::ReadText(dir / "out.txt");
  EXPECT_NE(out.find("model.json"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "e.json"));
}

}  // namespace
}  // namespace bead::explain
