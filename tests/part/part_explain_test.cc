// bead explain on a part scan: its flow along the path is the series (the
// file bead flow writes), the screw's RPM the input and the head's speed a
// recorded cause; the report is the one series mode gives on that file.
// What belongs to a wheel's run is refused by name.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/run_cli.h"

namespace bead {
namespace {

TEST(PartExplain, APartScansFlowAlongThePathIsExplainedAsASeries) {
  test::TempDir dir;
  test::WriteText(dir / "wall.yaml", "seed: 7\npart: {shape: wall, layers: 3, length_mm: 60}\n");
  auto [code, out] = test::RunCli(dir, "simulate " + (dir / "wall.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(code, 0) << out;
  const std::string twin = dir / "twin", rig = " --rig " + twin + "/rig.yaml ";
  std::tie(code, out) = test::RunCli(dir, "explain" + rig + twin + "/part.h5 -o " + (dir / "part.json"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("the flow along the path (bead flow's) is the series"), std::string::npos) << out;
  // The flow is read from a scratch copy, but what is said is said of the scan.
  EXPECT_NE(out.find("part.h5's flow along the path: "), std::string::npos) << out;
  EXPECT_EQ(out.find("_flow.csv"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, "flow" + rig + twin + "/part.h5 -o " + (dir / "flow.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(dir, "explain " + (dir / "flow.csv") +
                                              " --time t_s --input screw_rpm --output flow_mm3_s --channels "
                                              "head_speed_mm_s -o " +
                                              (dir / "csv.json"));
  ASSERT_EQ(code, 0) << out;
  nlohmann::json part = nlohmann::json::parse(test::ReadText(dir / "part.json"));
  nlohmann::json csv = nlohmann::json::parse(test::ReadText(dir / "csv.json"));
  EXPECT_EQ(part["mode"], "part");
  EXPECT_EQ(csv["mode"], "csv");
  EXPECT_NE(part["model"]["source"].get<std::string>().find("part.h5's flow along the path"), std::string::npos)
      << part["model"]["source"];
  part.erase("mode"), csv.erase("mode");
  part["model"].erase("source"), csv["model"].erase("source");
  EXPECT_EQ(part, csv);
  EXPECT_GT(part["fit_before_pct"].get<double>(), 0.0);

  // A wheel's options, and CSV mode's columns, are refused by name.
  std::tie(code, out) =
      test::RunCli(dir, "explain" + rig + twin + "/part.h5 --flow-out " + (dir / "c.csv") + " -o " + (dir / "x.json"));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("a part scan has no encoder"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, "explain" + rig + twin + "/part.h5 --input screw_rpm -o " + (dir / "x.json"));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("a part scan's series is its flow along the path"), std::string::npos) << out;
}

}  // namespace
}  // namespace bead
