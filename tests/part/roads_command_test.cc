// bead measure --beads all: the spec's one row per bead, on a layer of
// roads the twin printed and on the bundled wheel run (one bead each).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/csv_rows.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

using test::CsvRows;

TEST(RoadsCommand, ALayerOfRoadsGetsOneRowPerRoadNearItsTruth) {
  test::TempDir dir;
  auto [code, out] = test::RunCli(
      dir, "simulate " + std::string(BEAD_SOURCE_DIR) + "/testdata/configs/part_roads.yaml -o " + (dir / "sim"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("4 roads"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, "measure --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") +
                                              " --beads all -o " + (dir / "beads.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("with 4 beads"), std::string::npos) << out;
  EXPECT_NE(out.find("tangent overlapping model"), std::string::npos) << out;
  EXPECT_NE(out.find("area_corrected_mm2 is left empty"), std::string::npos) << out;
  const auto beads = CsvRows(dir / "beads.csv"), truth = CsvRows(dir / "sim/truth_roads.csv");
  const std::vector<std::string> spec = {
      "profile", "bead", "t_s", "center_x_mm", "area_mm2", "width_mm", "height_mm", "area_corrected_mm2", "valid"};
  ASSERT_GE(beads[0].size(), spec.size());
  for (std::size_t k = 0; k < spec.size(); ++k) EXPECT_EQ(beads[0][k], spec[k]);
  // The config's roads (0.85 w apart): every one found, in the truth's
  // order; centre within the 0.3 mm, area within its 5 %.
  ASSERT_EQ(beads.size(), truth.size());
  for (std::size_t i = 1; i < beads.size(); ++i) {
    ASSERT_EQ(beads[i][0], truth[i][0]);
    ASSERT_EQ(beads[i][1], truth[i][1]);
    EXPECT_EQ(beads[i][8], "1");
    EXPECT_NEAR(std::stod(beads[i][3]), std::stod(truth[i][3]), 0.3) << i;
    EXPECT_NEAR(std::stod(beads[i][4]) / std::stod(truth[i][2]), 1.0, 0.05) << i;
  }
}

// The same roads with the rig's reference areas laid over them: a line
// laid there stands on the roads, not on the bed, and every road measured
// over it would be a fraction of itself. Over the outer roads' tops, the
// areas are no line to the noise; over an outer road's flank, its points
// stand over the line the bare rest gives. No profile is measured either
// way; the status and the tool say why and what to set.
TEST(RoadsCommand, ReferenceAreasOnTheRoadsAreRefusedNotMeasuredAsTheBed) {
  test::TempDir dir;
  auto [code, out] = test::RunCli(
      dir, "simulate " + std::string(BEAD_SOURCE_DIR) + "/testdata/configs/part_roads.yaml -o " + (dir / "sim"));
  ASSERT_EQ(code, 0) << out;
  std::string rig = test::ReadText(dir / "sim/rig.yaml");
  const std::size_t at = rig.find("reference_areas_mm:");
  ASSERT_NE(at, std::string::npos) << rig;
  const struct {
    std::string areas, status, said;
  } cases[] = {{"[[-9, -5], [5, 9]]", "reference_not_a_line", "are no line to the profile's noise"},
               {"[[-15, -10.2], [10.2, 15]]", "bead_in_reference_area", "have a bead standing in the rig's reference"}};
  for (const auto& c : cases) {
    test::WriteText(dir / "on_roads.yaml", rig.substr(0, at) + "reference_areas_mm: " + c.areas + "\n");
    for (const std::string beads : {" --beads all", ""}) {
      std::tie(code, out) = test::RunCli(dir, "measure --rig " + (dir / "on_roads.yaml") + " " + (dir / "sim/part.h5") +
                                                  beads + " -o " + (dir / "out.csv"));
      ASSERT_EQ(code, 0) << out;
      EXPECT_NE(out.find(c.said), std::string::npos) << out;
      const auto rows = CsvRows(dir / "out.csv");
      if (!beads.empty()) {
        EXPECT_EQ(rows.size(), 1u) << "no road is measured over a bed line laid on the roads";
        // Those profiles were not measured: not counted as showing no bead.
        EXPECT_EQ(out.find("with 0 beads"), std::string::npos) << out;
        EXPECT_EQ(out.find("measured with no bead"), std::string::npos) << out;
        continue;
      }
      ASSERT_GT(rows.size(), 1u);
      const auto status = std::find(rows[0].begin(), rows[0].end(), "status") - rows[0].begin();
      for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i][status], c.status) << c.areas << " " << i;
    }
  }
}

TEST(RoadsCommand, TheWheelsOneBeadIsOneBeadWithTheWheelsArea) {
  test::TempDir dir;
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample/";
  auto [code, out] = test::RunCli(
      dir, "measure --rig " + sample + "rig.yaml " + sample + "run.h5 --beads all -o " + (dir / "beads.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) =
      test::RunCli(dir, "measure --rig " + sample + "rig.yaml " + sample + "run.h5 -o " + (dir / "geo.csv"));
  ASSERT_EQ(code, 0) << out;
  const auto beads = CsvRows(dir / "beads.csv"), geo = CsvRows(dir / "geo.csv");
  std::map<std::string, int> per_profile;
  for (std::size_t i = 1; i < beads.size(); ++i) ++per_profile[beads[i][0]];
  int valid = 0;
  for (std::size_t i = 1; i < geo.size(); ++i) {
    if (geo[i][7] != "1") continue;
    ++valid;
    const std::string& profile = geo[i][0];
    ASSERT_EQ(per_profile[profile], 1) << "profile " << profile;
  }
  EXPECT_GT(valid, 1000);
  // The same bare points either side, the same trapezoid: the areas agree
  // to rounding in most profiles; where the two stages treat a spike or a
  // foot's point differently, by at most that point's strip (the sample's
  // points lie 0.125 mm apart, the strip as high as the bead).
  std::vector<double> relative;
  for (std::size_t i = 1; i < beads.size(); ++i) {
    const auto& g = geo[std::stoul(beads[i][0]) + 1];
    if (g[7] != "1") continue;
    const double area = std::stod(beads[i][4]), wheel = std::stod(g[3]);
    EXPECT_NEAR(area, wheel, 0.125 * std::stod(g[5])) << "profile " << beads[i][0];
    relative.push_back(std::abs(area / wheel - 1.0));
  }
  std::nth_element(relative.begin(), relative.begin() + relative.size() / 2, relative.end());
  EXPECT_LT(relative[relative.size() / 2], 1e-3);
}

TEST(RoadsCommand, ABadBeadsOrOrderIsAUsageError) {
  test::TempDir dir;
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample/";
  auto [code, out] = test::RunCli(
      dir, "measure --rig " + sample + "rig.yaml " + sample + "run.h5 --beads two -o " + (dir / "beads.csv"));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("--beads"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, "measure --rig " + sample + "rig.yaml " + sample +
                                              "run.h5 --beads all --laid upward -o " + (dir / "beads.csv"));
  EXPECT_EQ(code, 2) << out;
}

}  // namespace
}  // namespace bead
