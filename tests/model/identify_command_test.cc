// `bead identify` on weld-style runs whose input has its own file and
// clock, validated on a second run: that run needs its own input file (it
// must never be paired with the first run's input), and the arc's strike
// is reported as a start from rest.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

#include "libbead/model/identify.h"
#include "tests/support/random_steps.h"
#include "tests/support/run_cli.h"

namespace bead::model {
namespace {

// Width (0 until the arc strikes at 3 s, then K u(t - Td) through 1/(T s + 1)
// from rest) every 0.04 s; the wire feed in steps on its own 4 ms clock.
void WriteRun(const test::TempDir& dir, const std::string& name, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto [tu, u] = test::RandomSteps(rng, 3.0, 7.0, 10001, 300, 0.004);
  std::vector<double> ty, uy;
  for (int i = 0; i < 1000; ++i) {
    ty.push_back(0.04 * i);
    uy.push_back(u[static_cast<std::size_t>(std::lround(std::floor(ty.back() / 0.004 + 1e-9)))]);
  }
  Segment arc{75, ty.size(), true};  // at rest at 3.00 s
  const std::vector<double> w = Predict({{1.2}, {0.5, 1.0}, 0.1}, 0.0, ty, uy, {}, {arc});
  std::string wcsv = "t,w\n", ucsv = "t,wfs\n";
  for (std::size_t i = 0; i < ty.size(); ++i)
    wcsv += std::to_string(ty[i]) + "," + std::to_string(i < arc.begin ? 0.0 : w[i] + noise(rng)) + "\n";
  for (std::size_t i = 0; i < tu.size(); ++i) ucsv += std::to_string(tu[i]) + "," + std::to_string(u[i]) + "\n";
  test::WriteText(dir / (name + "_w.csv"), wcsv);
  test::WriteText(dir / (name + "_wfs.csv"), ucsv);
}

TEST(IdentifyCommand, ValidationRunWithItsOwnInputFile) {
  test::TempDir dir;
  WriteRun(dir, "a", 1);
  WriteRun(dir, "b", 2);
  const std::string common = "identify " + (dir / "a_w.csv") + " --time t --output w --input wfs --input-file " +
                             (dir / "a_wfs.csv") + " --structure P1D --validate " + (dir / "b_w.csv");
  auto [status, out] = test::RunCli(dir, common + " -o " + (dir / "m.json"));
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("--validate-input-file"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));
  std::tie(status, out) =
      test::RunCli(dir, common + " --validate-input-file " + (dir / "b_wfs.csv") + " -o " + (dir / "m.json"));
  ASSERT_EQ(status, 0) << out;
  // Noise 0.02 against a width that varies by ~1.2 (std): fit ~98 %; the
  // input joined at the output's times costs at most a sample's timing.
  const auto at = out.find("fit on validation data");
  ASSERT_NE(at, std::string::npos) << out;
  const double fit = std::stod(out.substr(out.find("): ", at) + 3));
  EXPECT_GT(fit, 95.0) << out;
  const auto j = nlohmann::json::parse(test::ReadText(dir / "m.json"));
  ASSERT_EQ(j["initial_state"].size(), 1u);
  EXPECT_EQ(j["initial_state"][0]["from"], "rest: the process started");
  EXPECT_NEAR(j["initial_state"][0]["t_s"].get<double>(), 3.0, 1e-6);
}

}  // namespace
}  // namespace bead::model
