// bead report: one page that opens offline, with every section the run
// has data for, the pictures inside it; without pins or explain, no such
// section; a failed drawing leaves no page behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "tests/support/run_cli.h"

namespace bead {
namespace {

TEST(ReportCommand, OnePageWithEverySectionAndNothingOutside) {
  test::TempDir dir;
  test::WriteText(dir / "sim.yaml", "seed: 4\nduration_s: 4\nsensor: {points: 200}\npins: {scans: 3}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  const std::string twin = dir / "twin";
  auto [ex, ex_out] = test::RunCli(
      dir, "explain --occlusion none --rig " + twin + "/rig.yaml " + twin + "/run.h5 -o " + (dir / "explain.json"));
  ASSERT_EQ(ex, 0) << ex_out;
  auto [status, out] =
      test::RunCli(dir, "report --rig " + twin + "/rig.yaml " + twin + "/run.h5 --pins " + twin +
                            "/pins.h5 --explain " + (dir / "explain.json") + " -o " + (dir / "r.html"));
  ASSERT_EQ(status, 0) << out;
  const std::string page = test::ReadText(dir / "r.html");
  ASSERT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  for (const char* id : {"summary", "profiles", "geometry", "flow", "explain", "pins"})
    EXPECT_EQ(test::Occurrences(page, std::string("<section id=\"") + id + "\">"), 1) << id;
  // Pictures: profiles, geometry, flow, the model against the data, the
  // residual's correlations, its spectrum, pins; all inside the page.
  EXPECT_EQ(test::Occurrences(page, "<img alt=\"\" src=\"data:image/png;base64,"), 7);
  for (const char* h : {"Model against the data", "Residual</h3>", "Residual spectrum", "Encoder offset"})
    EXPECT_EQ(test::Occurrences(page, h), 1) << h;
  EXPECT_NE(page.find("rig file</td>"), std::string::npos);
  EXPECT_EQ(test::Occurrences(page, "<script"), 0);
  EXPECT_FALSE(std::regex_search(page, std::regex(R"((src|href)=\"(https?:|file:|/))"))) << "a link outside the page";
  EXPECT_NE(page.find("profiles</td><td>801</td>"), std::string::npos);  // 4 s at 200 Hz, both ends
  EXPECT_NE(page.find("scans used"), std::string::npos);

  auto [imp, imp_out] =
      test::RunCli(dir, "report --rig " + twin + "/rig.yaml " + twin + "/run.h5 -o " + (dir / "r2.html"));
  ASSERT_EQ(imp, 0) << imp_out;
  // A page without pins or explain has neither section.
  const std::string page2 = test::ReadText(dir / "r2.html");
  EXPECT_EQ(test::Occurrences(page2, "<section id=\"pins\">"), 0);
  EXPECT_EQ(test::Occurrences(page2, "<section id=\"explain\">"), 0);

  // The drawing fails (a python that cannot run the script): an error, and no page.
  const std::string env_cmd = "BEAD_PYTHON=/bin/false " + std::string(BEAD_CLI) + " report --rig " + twin +
                              "/rig.yaml " + twin + "/run.h5 -o " + (dir / "r3.html") + " >" + (dir / "o3.txt") +
                              " 2>&1";
  EXPECT_NE(std::system(env_cmd.c_str()), 0);
  EXPECT_NE(test::ReadText(dir / "o3.txt").find("r3.html: the report script"), std::string::npos)
      << test::ReadText(dir / "o3.txt");
  EXPECT_FALSE(std::filesystem::exists(dir / "r3.html"));
}

// What the report is given is checked before the run is measured: an
// output folder that does not exist, an --explain file of another kind (a
// model file), each answered in one line, exit 1, no traceback.
TEST(ReportCommand, OutputAndExplainFileAreCheckedBeforeAnyWork) {
  test::TempDir dir;
  test::WriteText(dir / "sim.yaml", "seed: 4\nduration_s: 2\nsensor: {points: 100}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  const std::string run = "--rig " + (dir / "twin/rig.yaml") + " " + (dir / "twin/run.h5");
  auto [status, out] = test::RunCli(dir, "report " + run + " -o " + (dir / "nodir/r.html"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("nodir/r.html: cannot write: folder"), std::string::npos) << out;
  EXPECT_EQ(test::Occurrences(out, "\n"), 1) << out;
  test::WriteText(dir / "model.json", R"({"num": [1], "den": [1, 1], "delay_s": 0.1})");
  std::tie(status, out) =
      test::RunCli(dir, "report " + run + " --explain " + (dir / "model.json") + " -o " + (dir / "r.html"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("model.json: is a model file (bead identify -o): --explain takes an explain report"),
            std::string::npos)
      << out;
  EXPECT_EQ(test::Occurrences(out, "\n"), 1) << out;
  EXPECT_EQ(out.find("Traceback"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "r.html"));
}

}  // namespace
}  // namespace bead
