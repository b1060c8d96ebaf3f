// bead report on a part scan (format 1.1): each layer in brief, the
// cross-sections stacked, the area and height along the path, the flow
// against the head's speed; the layers' numbers on the page are the
// material the twin laid, and a scan that lacks what a section needs says
// so instead of drawing nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/csv_rows.h"
#include "tests/support/run_cli.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

// The layers table's rows: layer, profiles, valid, area seen, area
// corrected, height, pass shift, volume.
std::vector<std::vector<std::string>> LayerRows(const std::string& page) {
  const std::size_t from = page.find("<section id=\"layers\">");
  const std::string section = page.substr(from, page.find("</section>", from) - from);
  std::vector<std::vector<std::string>> rows;
  const std::regex row(R"(<tr>((<td>[^<]*</td>)+)</tr>)"), cell(R"(<td>([^<]*)</td>)");
  for (auto r = std::sregex_iterator(section.begin(), section.end(), row); r != std::sregex_iterator(); ++r) {
    std::vector<std::string> cells;
    const std::string s = (*r)[1];
    for (auto c = std::sregex_iterator(s.begin(), s.end(), cell); c != std::sregex_iterator(); ++c)
      cells.push_back((*c)[1]);
    rows.push_back(cells);
  }
  return rows;
}

using test::Median;

TEST(PartReport, EachLayersRowIsTheMaterialTheTwinLaid) {
  test::TempDir dir;
  test::WriteText(dir / "wall.yaml", "seed: 3\npart: {shape: wall, layers: 3, length_mm: 60}\n");
  auto [code, out] = test::RunCli(dir, "simulate " + (dir / "wall.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(code, 0) << out;
  const std::string twin = dir / "twin";
  std::tie(code, out) =
      test::RunCli(dir, "report --rig " + twin + "/rig.yaml " + twin + "/part.h5 -o " + (dir / "p.html"));
  ASSERT_EQ(code, 0) << out;
  const std::string page = test::ReadText(dir / "p.html");
  for (const char* id : {"summary", "layers", "sections", "path", "speed"})
    EXPECT_EQ(test::Occurrences(page, std::string("<section id=\"") + id + "\">"), 1) << id;
  EXPECT_EQ(test::Occurrences(page, "<img alt=\"\" src=\"data:image/png;base64,"),
            3);  // sections, along the path, speed
  EXPECT_FALSE(std::regex_search(page, std::regex(R"((src|href)=\"(https?:|file:|/))"))) << "a link outside the page";

  // The twin's truth per layer: the material laid (mean) and the height gained (median).
  std::map<int, std::vector<double>> area, height;
  const auto truth = test::CsvRows(twin + "/truth.csv");
  for (std::size_t i = 1; i < truth.size(); ++i) {
    area[std::stoi(truth[i][0])].push_back(std::stod(truth[i][2]));
    height[std::stoi(truth[i][0])].push_back(std::stod(truth[i][4]));
  }
  const auto rows = LayerRows(page);
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) {
    ASSERT_EQ(r.size(), 8u);
    const int layer = std::stoi(r[0]);
    double mean = 0;
    for (double a : area[layer]) mean += a / static_cast<double>(area[layer].size());
    // The issue's bars for a wall: area unbiased within 1 % over the run,
    // layer height within 0.05 mm (median).
    EXPECT_NEAR(std::stod(r[4]), mean, 0.01 * mean) << "layer " << layer;
    EXPECT_NEAR(std::stod(r[5]), Median(height[layer]), 0.05) << "layer " << layer;
    // The overhang hides a groove on the layers above the first: what is seen is more than was laid.
    if (layer > 0) {
      EXPECT_GT(std::stod(r[3]), std::stod(r[4])) << "layer " << layer;
    }
  }

  // Pins belong to a wheel's encoder: refused before any work.
  std::tie(code, out) = test::RunCli(dir, "report --rig " + twin + "/rig.yaml " + twin + "/part.h5 --pins " + twin +
                                              "/part.h5 -o " + (dir / "q.html"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("is a part scan, which has no encoder"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "q.html"));
}

// Another lab's single layer (testdata/realdata/bead-observer, MIT): no
// layer below, no log; the page says why rather than drawing empty plots.
TEST(PartReport, AScanWithoutTheLayerBelowSaysWhy) {
  test::TempDir dir;
  const std::string csv =
      std::string(BEAD_SOURCE_DIR) + "/testdata/realdata/bead-observer/Representative_Layer_raw_points.csv";
  auto [code, out] = test::RunCli(dir, "import " + csv + " -o " + (dir / "l25.h5") +
                                           " --profile-column ScanID --time-column Timestamp --x-column X --z-column Z"
                                           " --z-distance --layer-column Layer --head-speed-mm-s 10");
  ASSERT_EQ(code, 0) << out;
  test::WriteText(dir / "rig.yaml", "part: {bed: flat}\nsensor:\n  reference_areas_mm: [[0, 1], [8, 9]]\n");
  std::tie(code, out) =
      test::RunCli(dir, "report --rig " + (dir / "rig.yaml") + " " + (dir / "l25.h5") + " -o " + (dir / "p.html"));
  ASSERT_EQ(code, 0) << out;
  const std::string page = test::ReadText(dir / "p.html");
  EXPECT_NE(page.find("layer 25: layer 24 is not in the scan"), std::string::npos);
  EXPECT_NE(page.find("invalid: no_surface_below</td><td>399"), std::string::npos);
  EXPECT_NE(page.find("No valid profile"), std::string::npos);
  EXPECT_NE(page.find("none: the scan has no /log"), std::string::npos);
  EXPECT_EQ(test::Occurrences(page, "<section id=\"speed\">"), 0);
  EXPECT_EQ(test::Occurrences(page, "<img alt=\"\" src=\"data:image/png;base64,"), 1);  // its cross-sections
}

}  // namespace
}  // namespace bead
