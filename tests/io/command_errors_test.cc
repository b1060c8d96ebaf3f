// Bad input to every command: exit status 1 and one line naming the file,
// the place in it and what is wrong (never a crash, never a success with
// nothing in it); what is odd but usable runs to the end with a warning.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>

#include <string>
#include <vector>

#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_writer.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

struct Case {
  std::string args;                 // after `bead`, with {} for the test's folder
  std::vector<std::string> expect;  // each part of the output
};

std::string Fill(std::string s, const std::string& dir) {
  for (std::size_t at; (at = s.find("{}")) != std::string::npos;) s.replace(at, 2, dir);
  return s;
}

TEST(CommandErrors, EachCommandNamesTheFileAndThePlace) {
  test::TempDir dir;
  std::string rows = "t,u,y\n";
  for (int i = 0; i < 30; ++i) rows += std::to_string(0.1 * i) + ",1," + (i == 3 ? "N/A" : "x") + "\n";
  test::WriteText(dir / "text.csv", rows);
  std::string good = "t,u,y\n";
  for (int i = 0; i < 60; ++i)
    good += std::to_string(0.1 * i) + "," + std::to_string(i / 10 % 2) + "," + std::to_string(i / 10 % 2) + "\n";
  test::WriteText(dir / "good.csv", good);
  test::WriteText(dir / "broken.json", "{\"num\": [1]");
  test::WriteText(dir / "vendor.csv", "Layer,ScanID\n1,2\n");
  test::WriteText(dir / "plane.yaml", "points:\n  - [1, 2, 3]\n");
  test::WriteText(dir / "good_plane.yaml",
                  "points:\n  - [102.5, 388.0, -20.0, 0.0]\n  - [880.0, 391.5, 20.0, 0.0]\n"
                  "  - [110.0, 120.0, -20.0, 30.0]\n  - [872.0, 118.0, 20.0, 30.0]\n");
  test::WriteText(dir / "frame.png", "not an image");
  test::WriteText(dir / "sim.yaml", "seed: x\n");
  test::WriteText(dir / "rig.yaml",
                  "encoder: {counts_per_rev: -5, bits: 32, direction: 1}\nwheel: {diameter_mm: 254.762}\n"
                  "offset: {counts: 3071.5}\nsensor: {reference_areas_mm: [[-24, -12], [12, 24]]}\n");
  test::WriteText(dir / "manifest.csv", "run,placement\nrun/run.h5,run/rig.yaml\n");
  sim::SimConfig c;
  c.duration_s = 0.1;
  c.sensor.points = 40;
  c.pins.scans = 2;
  sim::WriteSimulatedRun(dir / "run", sim::Simulate(c));
  const std::vector<Case> cases = {
      {"identify {}/text.csv --time t --input u --output y",
       {"text.csv: fewer than 20 usable rows", "line 2, column 'y': 'x' is not a finite number"}},
      {"identify {}/good.csv --time t --input u --output nope", {"good.csv: line 1: no column 'nope'"}},
      {"explain {}/good.csv --time t --input u --output y --model {}/broken.json -o {}/e.json",
       {"broken.json", "not JSON"}},
      {"identify {}/good.csv --time t --input u --output y --input-file {}/good.csv --validate {}/good.csv",
       {"needs --validate-input-file"}},
      {"import {}/vendor.csv -o {}/r.h5 --profile-column ScanID --time-column Timestamp --x-column X --z-column Z",
       {"vendor.csv: line 1: no column 'Timestamp'"}},
      {"frames --plane {}/plane.yaml --rate-hz 10 {}/frame.png -o {}/f.h5",
       {"plane.yaml: line 2: points: each entry must be [u, v, x_mm, z_mm]"}},
      {"frames --plane {}/good_plane.yaml --rate-hz 10 {}/frame.png -o {}/f.h5",
       {"frame.png: not an image OpenCV can read"}},
      {"simulate {}/sim.yaml -o {}/simout", {"sim.yaml: line 1: seed: must be a number"}},
      {"calibrate offset --rig {}/run/rig.yaml {}/run/run.h5",
       {"run.h5: is a run archive (it holds /profiles): this takes a pin-scan archive"}},
      {"flow --rig {}/rig.yaml {}/run/run.h5 -o {}/flow.csv", {"rig.yaml", "counts_per_rev"}},
      {"measure --rig {}/run/rig.yaml {}/good.csv -o {}/g.csv", {"good.csv"}},
      {"batch --manifest {}/manifest.csv -o {}/out", {"manifest.csv: line 1", "rig"}},
  };
  for (const Case& k : cases) {
    const auto [status, out] = test::RunCli(dir, Fill(k.args, dir / ""));
    EXPECT_EQ(status, 1) << k.args << "\n" << out;
    for (const std::string& e : k.expect) EXPECT_NE(out.find(e), std::string::npos) << k.args << "\n" << out;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "e.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "f.h5"));
  EXPECT_FALSE(std::filesystem::exists(dir / "flow.csv"));
}

TEST(CommandLine, BeadListsEverySubcommandAndNamesAWrongOne) {
  test::TempDir dir;
  const auto [help_status, help] = test::RunCli(dir, "--help");
  EXPECT_EQ(help_status, 0);
  for (const char* name : {"measure", "flow", "batch", "calibrate", "simulate", "import", "export", "frames",
                           "identify", "explain", "report"}) {
    EXPECT_NE(help.find(std::string("  ") + name + " "), std::string::npos) << name << "\n" << help;
    const auto [status, out] = test::RunCli(dir, std::string(name) + " --help");
    EXPECT_EQ(status, 0) << name << "\n" << out;
    EXPECT_NE(out.find("bead " + std::string(name)), std::string::npos) << out;
  }
  const auto [status, out] = test::RunCli(dir, "mesure --rig r.yaml");
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("'mesure' is not a subcommand"), std::string::npos) << out;
}

// `bead measure`, `bead flow` and `bead batch` start without loading what
// they do not use: no OpenCV (about 100 shared libraries), and no Ceres
// (glog, SuiteSparse, BLAS: about 20), whose fit they load when it runs.
// `bead --version` prints the version; a --shard that names no shard is a
// usage error (exit 2), as the README says usage errors are.
TEST(CommandLine, VersionAndAShardOutOfRange) {
  test::TempDir dir;
  auto [status, out] = test::RunCli(dir, "--version");
  EXPECT_EQ(status, 0) << out;
  EXPECT_EQ(out, std::string("bead ") + BEAD_VERSION + "\n");
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  std::tie(status, out) = test::RunCli(
      dir, "batch --rig " + (dir / "rig.yaml") + " -o " + (dir / "out") + " --shard 3/2 " + (dir / "rig.yaml"));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--shard '3/2': K must be from 1 to N"), std::string::npos) << out;
}

// `bead flow` with nothing given writes the bundled sample's flow to
// ./flow.csv, but never over a flow.csv the user has there.
TEST(CommandLine, TheSamplesFlowNeverReplacesTheUsersFlowCsv) {
  test::TempDir dir;
  test::WriteText(dir / "flow.csv", "mine\n");
  const int status = std::system(("cd " + dir.path().string() + " && " + BEAD_CLI + " flow >out.txt 2>&1").c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << test::ReadText(dir / "out.txt");
  EXPECT_NE(test::ReadText(dir / "out.txt").find("flow.csv exists"), std::string::npos)
      << test::ReadText(dir / "out.txt");
  EXPECT_EQ(test::ReadText(dir / "flow.csv"), "mine\n");
}

TEST(CommandLine, MeasureFlowAndBatchLoadNoOpenCvNorCeres) {
  test::TempDir dir;
  for (const char* sub : {"measure", "flow", "batch"}) {
    const std::string cmd = "ldd " + std::string(BEAD_CLI) + "-" + sub + " > " + (dir / "ldd.txt");
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const std::string libs = test::ReadText(dir / "ldd.txt");
    EXPECT_NE(libs.find("libyaml-cpp"), std::string::npos) << sub << libs;  // it reads rig files
    for (const char* absent : {"libopencv", "libceres", "libglog", "libcholmod"})
      EXPECT_EQ(libs.find(absent), std::string::npos) << sub << " loads " << absent << ":\n" << libs;
  }
}

// The fit is loaded when it runs; a program without its module says what
// to do, and runs with --occlusion none.
TEST(CommandLine, MeasureWithoutItsOcclusionModuleSaysSo) {
  namespace fs = std::filesystem;
  test::TempDir dir;
  const fs::path lone = dir / "bead-measure";
  fs::copy_file(std::string(BEAD_CLI) + "-measure", lone);
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample/";
  const std::string args = " measure --rig " + sample + "rig.yaml " + sample + "run.h5 -o " + (dir / "g.csv");
  const int pooled = std::system((lone.string() + args + " > " + (dir / "out.txt") + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(pooled), 1);
  const std::string out = test::ReadText(dir / "out.txt");
  EXPECT_NE(out.find("bead-occlusion-fit.so"), std::string::npos) << out;
  EXPECT_NE(out.find("--occlusion none"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "g.csv"));
  const int none = std::system((lone.string() + args + " --occlusion none > " + (dir / "out.txt") + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(none), 0) << test::ReadText(dir / "out.txt");
  EXPECT_TRUE(fs::exists(dir / "g.csv"));
}

}  // namespace
}  // namespace bead
