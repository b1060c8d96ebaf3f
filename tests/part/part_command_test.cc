// bead simulate prints a part, bead measure measures it layer on layer
// (part mode chosen by the archive's kind), the wheel's commands name it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/csv_rows.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

using test::CsvRows;

// The twin of `config` printed to dir/sim and measured to dir/geo.csv:
// what bead measure printed (empty, the test failed, where either failed).
std::string SimulatedAndMeasured(const test::TempDir& dir, const std::string& config) {
  {
    std::ofstream cfg(dir / "part.yaml");
    cfg << config;
  }
  auto [code, out] = test::RunCli(dir, "simulate " + (dir / "part.yaml") + " -o " + (dir / "sim"));
  EXPECT_EQ(code, 0) << out;
  if (code != 0) return "";
  std::tie(code, out) = test::RunCli(
      dir, "measure --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "geo.csv"));
  EXPECT_EQ(code, 0) << out;
  return code == 0 ? out : "";
}

TEST(PartCommand, SimulateThenMeasureWritesThePartGeometryCsv) {
  test::TempDir dir;
  std::string out = SimulatedAndMeasured(dir, "seed: 4\npart:\n  layers: 3\n  length_mm: 20\n");
  ASSERT_FALSE(out.empty());
  EXPECT_NE(out.find("part scan"), std::string::npos) << out;
  EXPECT_NE(out.find("layer 2:"), std::string::npos) << out;
  // Each layer's bead shape, pooled on its first profiles: the twin's
  // ellipse (exponent 2, to well within a tenth: its sigma ~0.005).
  const std::size_t shape = out.find("exponent ");
  ASSERT_NE(shape, std::string::npos) << out;
  EXPECT_NEAR(std::stod(out.substr(shape + 9)), 2.0, 0.05) << out;
  const auto geo = CsvRows(dir / "geo.csv"), truth = CsvRows(dir / "sim/truth.csv");
  ASSERT_GT(geo.size(), 2u);
  const std::vector<std::string> spec = {
      "profile", "t_s", "layer", "path_mm", "area_mm2", "width_mm", "height_mm", "area_corrected_mm2", "valid"};
  ASSERT_GE(geo[0].size(), spec.size());
  for (std::size_t k = 0; k < spec.size(); ++k) EXPECT_EQ(geo[0][k], spec[k]);
  ASSERT_EQ(geo.size(), truth.size());
  // Each row's area against the visible area the twin laid there, within
  // the bound the library's test derives (four walls of one spacing).
  for (std::size_t i = 1; i < geo.size(); ++i) {
    ASSERT_EQ(geo[i][8], "1") << i;
    EXPECT_EQ(geo[i][2], truth[i][0]);
    EXPECT_NEAR(std::stod(geo[i][4]), std::stod(truth[i][3]), 0.3) << i;
  }
  // The flow along the path: the spec's columns, a volume per layer.
  int code = 0;
  std::tie(code, out) = test::RunCli(
      dir, "flow --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "flow.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("layer 2: "), std::string::npos) << out;
  EXPECT_NE(out.find("total volume"), std::string::npos) << out;
  const auto flow = CsvRows(dir / "flow.csv");
  ASSERT_EQ(flow.size(), geo.size());
  const std::vector<std::string> flow_spec = {
      "t_s", "layer", "path_mm", "head_speed_mm_s", "area_mm2", "area_corrected_mm2", "flow_mm3_s", "screw_rpm"};
  for (std::size_t k = 0; k < flow_spec.size(); ++k) EXPECT_EQ(flow[0][k], flow_spec[k]);
}

// The profile options a user gives hold on every layer, not only on the
// bed's: a threshold over every bead's height (the twin's gain 2-3 mm a
// layer) finds no bead on any layer. (Given only to the processor that
// fits the bed's line, it changed no layer's bead: each was measured as if
// the threshold were 0.05 mm.)
TEST(PartCommand, AUsersThresholdHoldsOnEveryLayer) {
  test::TempDir dir;
  ASSERT_FALSE(SimulatedAndMeasured(dir, "seed: 4\npart:\n  layers: 3\n  length_mm: 20\n").empty());
  auto [code, out] = test::RunCli(dir, "measure --threshold-mm 10 --rig " + (dir / "sim/rig.yaml") + " " +
                                           (dir / "sim/part.h5") + " -o " + (dir / "high.csv"));
  ASSERT_EQ(code, 0) << out;
  const auto geo = CsvRows(dir / "geo.csv"), high = CsvRows(dir / "high.csv");
  ASSERT_EQ(geo.size(), high.size());
  std::vector<int> valid(3, 0), valid_high(3, 0);
  for (std::size_t i = 1; i < geo.size(); ++i) {
    const int layer = std::stoi(geo[i][2]);
    valid[layer] += geo[i][8] == "1", valid_high[layer] += high[i][8] == "1";
  }
  for (int layer = 0; layer < 3; ++layer) {
    EXPECT_GT(valid[layer], 0) << layer;
    EXPECT_EQ(valid_high[layer], 0) << "layer " << layer << ": a bead found under a 10 mm threshold";
  }
}

// Beads sunk so deep that their sides meet the surface below show no walls
// to solve their exponent on, and overhang nothing: no shape is claimed
// (not one found within two sigmas, nor the fits' aspect), and nothing is
// hidden, so the area seen stands as the corrected one.
TEST(PartCommand, AShapeNotSeenIsNotDescribed) {
  test::TempDir dir;
  const std::string out =
      SimulatedAndMeasured(dir, "seed: 4\npart:\n  layers: 1\n  length_mm: 20\n  area_mm2: 6\n  area_wave_mm2: 1\n");
  ASSERT_FALSE(out.empty());
  EXPECT_NE(out.find("bead shape: not seen (no bead of the layer overhangs"), std::string::npos) << out;
  EXPECT_EQ(out.find("half-height over half-width"), std::string::npos) << out;
  EXPECT_EQ(out.find("within two sigmas"), std::string::npos) << out;
}

// A bead whose whole outline holds less than the area asked of it would
// float off the surface below: the twin says so and writes nothing. (The
// twin's 6 mm bead of aspect 0.5 holds 14.1 mm^2 as an ellipse, 12.8 as a
// superellipse of exponent 1.6: 12 + 2 fits the one, not the other.)
TEST(PartCommand, ABeadThatCannotHoldItsAreaIsRefused) {
  test::TempDir dir;
  {
    std::ofstream cfg(dir / "wall.yaml");
    cfg << "part:\n  layers: 2\n  length_mm: 10\n  exponent: 1.6\n";
  }
  const auto [code, out] = test::RunCli(dir, "simulate " + (dir / "wall.yaml") + " -o " + (dir / "sim"));
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("part.area_mm2"), std::string::npos) << out;
  EXPECT_NE(out.find("float"), std::string::npos) << out;
  EXPECT_FALSE(std::ifstream(dir / "sim/part.h5").good());
}

TEST(PartCommand, TheWheelsCommandsNameAPartScanAndAPartRigNamesWhatIsMissing) {
  test::TempDir dir;
  {
    std::ofstream cfg(dir / "wall.yaml");
    cfg << "part:\n  layers: 2\n  length_mm: 5\n";
    std::ofstream rig(dir / "bare.yaml");
    rig << "part: {bed: flat}\n";
  }
  ASSERT_EQ(test::RunCli(dir, "simulate " + (dir / "wall.yaml") + " -o " + (dir / "sim")).first, 0);
  // bead explain takes a part scan (its flow along the path); 5 mm of it are too few samples, and the
  // error names the scan's flow, not the scratch file it was written to.
  auto [code, out] = test::RunCli(
      dir, "explain --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "e.json"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("part.h5's flow along the path: fewer than 20 usable rows"), std::string::npos) << out;
  EXPECT_EQ(out.find("/tmp/bead-explain-"), std::string::npos) << out;
  // A wheel's command: with a part rig, the rig is named; with a rig that has the wheel too, the archive.
  std::tie(code, out) = test::RunCli(
      dir, "calibrate wheel --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "w.yaml"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("this is a part rig"), std::string::npos) << out;
  {
    std::ofstream both(dir / "both.yaml");
    both << test::kCliRigYaml << "part: {bed: flat}\n";
  }
  std::tie(code, out) = test::RunCli(
      dir, "calibrate wheel --rig " + (dir / "both.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "w.yaml"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("is a part scan"), std::string::npos) << out;
  EXPECT_NE(out.find("bead measure, flow, report, explain, export and batch take a part scan"), std::string::npos)
      << out;
  std::tie(code, out) = test::RunCli(
      dir, "measure --rig " + (dir / "bare.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "geo.csv"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("bare.yaml"), std::string::npos) << out;
  EXPECT_NE(out.find("sensor"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, "simulate " + (dir / "bare.yaml") + " -o " + (dir / "x"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("line 1: part.bed: unknown key"), std::string::npos) << out;
}

}  // namespace
}  // namespace bead

namespace bead {
namespace {

// Another lab's layer scan (testdata/realdata/bead-observer: one layer, 25,
// of a thin wall, MIT): imported as a part scan with its Layer column and
// placed at the print's 10 mm/s, then measured: the layer below is not in
// the file, and every row says so instead of measuring against nothing.
TEST(PartCommand, AnotherLabsLayerScanIsImportedAndSaysWhatItLacks) {
  test::TempDir dir;
  const std::string csv =
      std::string(BEAD_SOURCE_DIR) + "/testdata/realdata/bead-observer/Representative_Layer_raw_points.csv";
  const std::string columns =
      " --profile-column ScanID --time-column Timestamp --x-column X --z-column Z --z-distance --layer-column Layer";
  auto [code, out] = test::RunCli(dir, "import " + csv + " -o " + (dir / "l25.h5") + columns + " --head-speed-mm-s 10");
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("a part scan: layers 25 to 25"), std::string::npos) << out;
  {
    std::ofstream rig(dir / "rig.yaml");
    rig << "part: {bed: flat}\nsensor:\n  reference_areas_mm: [[0, 1], [8, 9]]\n";
  }
  std::tie(code, out) =
      test::RunCli(dir, "measure --rig " + (dir / "rig.yaml") + " " + (dir / "l25.h5") + " -o " + (dir / "geo.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("layer 24 is not in the scan"), std::string::npos) << out;
  const auto rows = CsvRows(dir / "geo.csv");
  ASSERT_EQ(rows.size(), 400u);
  EXPECT_EQ(rows[1][16], "no_surface_below");  // the status column
  EXPECT_EQ(rows[1][2], "25");
  // Its place: 10 mm/s times the time since the layer's first profile.
  EXPECT_NEAR(std::stod(rows.back()[3]), 10.0 * (std::stod(rows.back()[1]) - std::stod(rows[1][1])), 1e-6);
  // Every bead of each profile: none, and the reason said, not invented.
  std::tie(code, out) = test::RunCli(
      dir, "measure --rig " + (dir / "rig.yaml") + " " + (dir / "l25.h5") + " --beads all -o " + (dir / "beads.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("399 profiles have no surface below"), std::string::npos) << out;
  EXPECT_EQ(CsvRows(dir / "beads.csv").size(), 1u);
  // Read with --first-layer 25 it is a first layer: its reference areas,
  // outside the 2.8-6.6 mm its points span, hold none of them, and the
  // tool says so rather than "0 valid" alone.
  std::tie(code, out) = test::RunCli(
      dir, "import " + csv + " -o " + (dir / "l0.h5") + columns + " --head-speed-mm-s 10 --first-layer 25");
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) =
      test::RunCli(dir, "measure --rig " + (dir / "rig.yaml") + " " + (dir / "l0.h5") + " -o " + (dir / "l0.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("399 profiles of layer 0 have no bed to measure against"), std::string::npos) << out;
  // A place is needed, one way only.
  std::tie(code, out) = test::RunCli(dir, "import " + csv + " -o " + (dir / "x.h5") + columns);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("--path-column, or --head-speed-mm-s"), std::string::npos) << out;
  std::tie(code, out) =
      test::RunCli(dir, "import " + csv + " -o " + (dir / "x.h5") + columns + " --path-column X --head-speed-mm-s 10");
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("not both"), std::string::npos) << out;
}

// A part scan exported to CSV and imported back without naming its frame
// heights (--frame-z-column): the import says every profile's is 0, and
// bead measure refuses the layers above the bed, saying why and by how much
// each lies under the one before it, not measuring a sliver of a bead. And
// imported with its heights taken for distances: every layer refused.
TEST(PartCommand, AScanImportedWithoutItsFrameHeightsOrWithItsZTurnedSaysSo) {
  test::TempDir dir;
  ASSERT_FALSE(SimulatedAndMeasured(dir, "part:\n  shape: wall\n  layers: 3\n  length_mm: 20\n").empty());
  auto [code, out] = test::RunCli(dir, "export " + (dir / "sim/part.h5") + " -o " + (dir / "part.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(
      dir, "import " + (dir / "part.csv") + " -o " + (dir / "flat.h5") +
               " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm --layer-column layer "
               "--path-column path_mm --frame-x-column frame_x_mm");
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("frame_z_mm is 0 mm in every layer (no --frame-z-column)"), std::string::npos) << out;
  std::tie(code, out) =
      test::RunCli(dir, "measure --rig " + (dir / "sim/rig.yaml") + " " + (dir / "flat.h5") + " -o " + (dir / "f.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("profiles' surface lies under the surface layer 0 left"), std::string::npos) << out;
  EXPECT_NE(out.find("/profiles/frame_z_mm must be the head's height"), std::string::npos) << out;
  const auto rows = CsvRows(dir / "f.csv");
  std::size_t under = 0, above = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i][2] == "0") continue;
    ++above;
    under += rows[i][16] == "under_surface_below";
  }
  EXPECT_GT(above, 60u);
  EXPECT_EQ(under, above);
  // Its heights read as distances from the sensor (--z-distance on a
  // height column): each bead a trough under the bed line, said so on the
  // bed's layer, none of its rows measured.
  std::tie(code, out) = test::RunCli(
      dir, "import " + (dir / "part.csv") + " -o " + (dir / "trough.h5") +
               " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm --layer-column layer "
               "--path-column path_mm --frame-z-column frame_z_mm --frame-x-column frame_x_mm --z-distance");
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(
      dir, "measure --rig " + (dir / "sim/rig.yaml") + " " + (dir / "trough.h5") + " -o " + (dir / "t.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("profiles of layer 0 lie under the bed line"), std::string::npos) << out;
  EXPECT_NE(out.find("its z is a distance from the sensor, not a height"), std::string::npos) << out;
  EXPECT_NE(out.find("layer 0: 40 profiles over path"), std::string::npos) << out;
  EXPECT_NE(out.find(", 0 valid (on the bed)"), std::string::npos) << out;
  // ... and the layers above: each one's bare bed lies off where the last
  // one's scan has it (its heights turned, the frame's rise doubled).
  EXPECT_NE(out.find("profiles' bare bed in the rig's reference areas lies"), std::string::npos) << out;
  // (Over it: a layer covering both areas at one height would look the
  // same, and the words say so.)
  EXPECT_NE(out.find("cannot tell from a frame one layer off"), std::string::npos) << out;
  for (const auto& row : CsvRows(dir / "t.csv")) {
    if (row[2] != "layer" && row[2] != "0") {
      EXPECT_EQ(row[16], "bed_moved") << row[0];
    }
  }
}

// The twin's log rewritten line by line: each data row's fields through
// `change` (t_s, layer, path_mm, screw_rpm; the head's speed left out).
void RewriteLog(const std::string& from, const std::string& to,
                const std::function<void(std::vector<std::string>&)>& change) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  std::getline(in, line);
  out << "t_s,layer,path_mm,screw_rpm\n";
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
    change(f);
    out << f[0] << ',' << f[1] << ',' << f[2] << ',' << f[3] << '\n';
  }
}

// A log whose places are not the scan's: its path in metres, or its layers
// counted from 1. bead flow says what the two span, or which layer the log
// never printed, beside the profiles it could not time.
TEST(PartCommand, ALogWhosePlacesAreNotTheScansSaysWhy) {
  test::TempDir dir;
  ASSERT_FALSE(SimulatedAndMeasured(dir, "part:\n  shape: wall\n  layers: 3\n  length_mm: 20\n").empty());
  auto [code, out] = test::RunCli(dir, "export " + (dir / "sim/part.h5") + " -o " + (dir / "part.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(dir, "export " + (dir / "sim/part.h5") + " --log -o " + (dir / "log.csv"));
  ASSERT_EQ(code, 0) << out;
  RewriteLog(dir / "log.csv", dir / "metres.csv", [](auto& f) { f[2] = std::to_string(std::stod(f[2]) / 1000.0); });
  RewriteLog(dir / "log.csv", dir / "from1.csv", [](auto& f) { f[1] = std::to_string(std::stoll(f[1]) + 1); });
  const std::string columns =
      " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm --layer-column layer "
      "--path-column path_mm --frame-z-column frame_z_mm --frame-x-column frame_x_mm --log ";
  for (const std::string log : {"metres", "from1"}) {
    std::tie(code, out) = test::RunCli(
        dir, "import " + (dir / "part.csv") + " -o " + (dir / (log + ".h5")) + columns + (dir / (log + ".csv")));
    ASSERT_EQ(code, 0) << out;
    std::tie(code, out) = test::RunCli(
        dir, "flow --rig " + (dir / "sim/rig.yaml") + " " + (dir / (log + ".h5")) + " -o " + (dir / (log + "_f.csv")));
    ASSERT_EQ(code, 0) << out;
    if (log == "metres") {
      EXPECT_NE(out.find("most profiles were never placed: the scan's path spans"), std::string::npos) << out;
      EXPECT_NE(out.find("over layers 0 to 2, the log's 0 .. 0.0"), std::string::npos) << out;
    } else {
      EXPECT_NE(out.find("the scan's layer 0 is not in the log (its layers 1 to 3)"), std::string::npos) << out;
    }
  }
}

}  // namespace
}  // namespace bead

namespace bead {
namespace {

std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// bead batch takes a part scan beside a wheel run: the part measured layer
// on layer, its files those bead measure and bead flow write, byte for byte.
TEST(PartCommand, BatchMeasuresAPartScanBesideAWheelRun) {
  test::TempDir dir;
  {
    std::ofstream cfg(dir / "wall.yaml");
    cfg << "seed: 9\npart:\n  layers: 2\n  length_mm: 15\n";
  }
  auto [code, out] = test::RunCli(dir, "simulate " + (dir / "wall.yaml") + " -o " + (dir / "sim"));
  ASSERT_EQ(code, 0) << out;
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample/";
  {
    std::ofstream manifest(dir / "runs.csv");
    manifest << "run,rig\n"
             << (dir / "sim/part.h5") << ',' << (dir / "sim/rig.yaml") << '\n'
             << sample << "run.h5," << sample << "rig.yaml\n";
  }
  std::tie(code, out) = test::RunCli(dir, "batch --manifest " + (dir / "runs.csv") + " -o " + (dir / "out"));
  ASSERT_EQ(code, 0) << out;
  const auto summary = CsvRows(dir / "out/summary.csv");
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[1][3], "ok") << out;
  EXPECT_EQ(summary[2][3], "ok") << out;
  std::tie(code, out) = test::RunCli(
      dir, "measure --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "geo.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(
      dir, "flow --rig " + (dir / "sim/rig.yaml") + " " + (dir / "sim/part.h5") + " -o " + (dir / "flow.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(FileText(dir / "out/part/geometry.csv"), FileText(dir / "geo.csv"));
  EXPECT_EQ(FileText(dir / "out/part/flow.csv"), FileText(dir / "flow.csv"));
  // The wheel run beside it keeps the wheel's columns.
  EXPECT_EQ(CsvRows(dir / "out/run/geometry.csv")[0][2], "encoder");
}

}  // namespace
}  // namespace bead
