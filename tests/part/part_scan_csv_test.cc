// A part scan's CSV forms: its profiles with their places and its nozzle
// log, written by bead export and made into the same part scan again by
// bead import (the files bead measure and bead flow write on it are the
// same, byte for byte); a log that is not a part log's, or not on the
// profiles' clock, is refused by file and line; a file that counts its
// layers from 1 is read with its first layer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "libbead/io/part_scan_csv.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

// The twin's two-layer wall in dir/twin, its profiles and log exported as
// dir/p.csv and dir/log.csv; false (and why, in `out`) where a step failed.
bool ExportedWall(const test::TempDir& dir, std::string& out) {
  test::WriteText(dir / "wall.yaml", "seed: 5\npart: {shape: wall, layers: 2, length_mm: 30}\n");
  const std::string twin = dir / "twin";
  for (const std::string& command :
       {"simulate " + (dir / "wall.yaml") + " -o " + twin, "export " + twin + "/part.h5 -o " + (dir / "p.csv"),
        "export " + twin + "/part.h5 --log -o " + (dir / "log.csv")}) {
    int code = 0;
    std::tie(code, out) = test::RunCli(dir, command);
    if (code != 0) return false;
  }
  return true;
}

// bead measure and bead flow on `archive` write what they write on the
// twin's own part.h5, byte for byte.
void ExpectMeasuredAsTheTwin(const test::TempDir& dir, const std::string& archive) {
  const std::string twin = dir / "twin", rig = " --rig " + twin + "/rig.yaml ";
  for (const char* command : {"measure", "flow"}) {
    auto [code, out] = test::RunCli(dir, std::string(command) + rig + twin + "/part.h5 -o " + (dir / "a.csv"));
    ASSERT_EQ(code, 0) << out;
    std::tie(code, out) = test::RunCli(dir, std::string(command) + rig + archive + " -o " + (dir / "b.csv"));
    ASSERT_EQ(code, 0) << out;
    EXPECT_EQ(test::ReadText(dir / "a.csv"), test::ReadText(dir / "b.csv")) << command;
  }
}

TEST(PartScanCsv, ExportedAndImportedTheScanMeasuresTheSame) {
  test::TempDir dir;
  std::string out;
  ASSERT_TRUE(ExportedWall(dir, out)) << out;
  int code = 0;
  const std::string twin = dir / "twin", rig = " --rig " + twin + "/rig.yaml ";
  EXPECT_EQ(test::ReadText(dir / "p.csv").rfind("profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm\n", 0), 0u);
  EXPECT_EQ(test::ReadText(dir / "log.csv").rfind("t_s,layer,path_mm,screw_rpm,head_speed_mm_s\n", 0), 0u);
  std::tie(code, out) = test::RunCli(
      dir, "import " + (dir / "p.csv") + " -o " + (dir / "back.h5") +
               " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm --layer-column layer"
               " --path-column path_mm --frame-z-column frame_z_mm --frame-x-column frame_x_mm --log " +
               (dir / "log.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("a part scan: layers 0 to 1"), std::string::npos) << out;
  EXPECT_NE(out.find("/log: "), std::string::npos) << out;
  ExpectMeasuredAsTheTwin(dir, dir / "back.h5");
  // The profiles CSV is a part scan as it stands: measured as the archive is, byte for byte; its flow
  // needs the log it cannot carry, and the tool says how to join them.
  std::tie(code, out) = test::RunCli(dir, "measure" + rig + twin + "/part.h5 -o " + (dir / "a.csv"));
  ASSERT_EQ(code, 0) << out;
  std::tie(code, out) = test::RunCli(dir, "measure" + rig + (dir / "p.csv") + " -o " + (dir / "b.csv"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(test::ReadText(dir / "a.csv"), test::ReadText(dir / "b.csv"));
  std::tie(code, out) = test::RunCli(dir, "flow" + rig + (dir / "p.csv") + " -o " + (dir / "c.csv"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("bead import it with --log LOG.csv"), std::string::npos) << out;
  // A log on another clock never meets the profiles: refused, nothing written.
  {
    std::ofstream late(dir / "late.csv");
    late << "t_s,layer,path_mm,screw_rpm\n1000,0,0,100\n1001,0,20,100\n";
  }
  std::tie(code, out) = test::RunCli(
      dir, "import " + (dir / "p.csv") + " -o " + (dir / "late.h5") +
               " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm --layer-column layer"
               " --path-column path_mm --log " +
               (dir / "late.csv"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("never meet the profiles'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "late.h5"));
}

// Another tool's file that counts its layers from 1: imported as it is,
// its first layer has nothing under it, and the import says how to read
// it; read with --first-layer 1, it is the same scan, measured the same.
std::string LayersPlusOne(const std::string& text, std::size_t column) {
  std::istringstream in(text);
  std::string line, out;
  std::getline(in, line), out += line + "\n";
  while (std::getline(in, line)) {
    std::size_t at = 0;
    for (std::size_t c = 0; c < column; ++c) at = line.find(',', at) + 1;
    const std::size_t end = line.find(',', at);
    out += line.substr(0, at) + std::to_string(std::stoll(line.substr(at, end - at)) + 1) + line.substr(end) + "\n";
  }
  return out;
}

TEST(PartScanCsv, AFileCountingItsLayersFromOneIsReadWithItsFirstLayer) {
  test::TempDir dir;
  std::string out;
  ASSERT_TRUE(ExportedWall(dir, out)) << out;
  int code = 0;
  test::WriteText(dir / "p1.csv", LayersPlusOne(test::ReadText(dir / "p.csv"), 2));
  test::WriteText(dir / "log1.csv", LayersPlusOne(test::ReadText(dir / "log.csv"), 1));
  const std::string import = "import " + (dir / "p1.csv") +
                             " --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm"
                             " --layer-column layer --path-column path_mm --frame-z-column frame_z_mm"
                             " --frame-x-column frame_x_mm --log " +
                             (dir / "log1.csv");
  std::tie(code, out) = test::RunCli(dir, import + " -o " + (dir / "as_is.h5"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("no layer 0 (the first layer, on the bed)"), std::string::npos) << out;
  EXPECT_NE(out.find("--first-layer 1"), std::string::npos) << out;
  std::tie(code, out) = test::RunCli(dir, import + " --first-layer 1 -o " + (dir / "back.h5"));
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("a part scan: layers 0 to 1"), std::string::npos) << out;
  EXPECT_EQ(out.find("no layer 0"), std::string::npos) << out;
  ExpectMeasuredAsTheTwin(dir, dir / "back.h5");
  // A first layer above the file's lowest is refused, naming it; nothing written.
  std::tie(code, out) = test::RunCli(dir, import + " --first-layer 2 -o " + (dir / "two.h5"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("layer 1 is below --first-layer 2"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "two.h5"));
  // So is a log whose layers go below it (a priming pass numbered 0).
  std::string log = test::ReadText(dir / "log1.csv");
  const std::size_t row = log.find('\n') + 1, layer = log.find(',', row) + 1;
  log.replace(layer, log.find(',', layer) - layer, "0");
  test::WriteText(dir / "log0.csv", log);
  std::tie(code, out) = test::RunCli(dir, import.substr(0, import.find(" --log ")) + " --log " + (dir / "log0.csv") +
                                              " --first-layer 1 -o " + (dir / "primed.h5"));
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("log0.csv: log sample 0: layer 0 is below --first-layer 1"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "primed.h5"));
  // A negative first layer is a usage error (it would number the bed's layer above 0).
  std::tie(code, out) = test::RunCli(dir, import + " --first-layer -1 -o " + (dir / "neg.h5"));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("--first-layer"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "neg.h5"));
}

TEST(PartScanCsv, AProfileWhoseRowsDisagreeOnItsPlaceIsRefusedAtItsLine) {
  test::TempDir dir;
  std::ofstream(dir / "p.csv") << "profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm\n"
                                  "0,0.1,0,1.5,60,0,-1,-60\n0,0.1,0,1.5,60,0,0,-59\n"
                                  "1,0.2,0,2.0,60,0,-1,-60\n1,0.2,0,2.5,60,0,0,-59\n";
  EXPECT_TRUE(IsPartProfilesCsv(dir / "p.csv"));
  test::ExpectRejected(dir / "p.csv", "line 5", [&] { ReadPartProfilesCsv(dir / "p.csv"); });
  std::ofstream(dir / "w.csv") << "profile,t_s,encoder,x_mm,z_mm\n0,0.1,5,-1,-60\n";
  EXPECT_FALSE(IsPartProfilesCsv(dir / "w.csv"));  // the wheel's profiles CSV
}

TEST(PartScanCsv, ALogThatIsNotAPartLogIsRefusedWhereItIsWrong) {
  test::TempDir dir;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const std::string wheel = write("wheel.csv", "t_s,encoder,screw_rpm\n0,0,100\n");
  test::ExpectRejected(wheel, "t_s,layer,path_mm,screw_rpm", [&] { ReadPartLogCsv(wheel); });
  const std::string negative = write("neg.csv", "t_s,layer,path_mm,screw_rpm\n0,0,0,100\n0.1,-1,1,100\n");
  test::ExpectRejected(negative, "a layer counts from 0", [&] { ReadPartLogCsv(negative); });
  const std::string word = write("word.csv", "t_s,layer,path_mm,screw_rpm\n0,0,zero,100\n");
  test::ExpectRejected(word, "path_mm", [&] { ReadPartLogCsv(word); });
  const std::string backwards = write("back.csv", "t_s,layer,path_mm,screw_rpm\n1,0,0,100\n0.5,0,1,100\n");
  test::ExpectRejected(backwards, "t_s", [&] { ReadPartLogCsv(backwards); });
  const std::string empty = write("empty.csv", "t_s,layer,path_mm,screw_rpm\n");
  test::ExpectRejected(empty, "holds no log rows", [&] { ReadPartLogCsv(empty); });
}

}  // namespace
}  // namespace bead
