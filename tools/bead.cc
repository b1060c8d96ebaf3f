// bead: the libbead command line. It lists the subcommands and hands each
// call over to the subcommand's own program, bead-<name>, beside it (exec:
// same process, same exit status), so that a call loads only the libraries
// its subcommand uses: `bead --help` none, `bead measure` no OpenCV.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "tools/own_folder.h"
#include "tools/subcommands.h"

namespace {

void PrintHelp() {
  std::printf(
      "bead: bead cross-sections and volumetric flow from laser line profiles (libbead)\n"
      "Usage: bead SUBCOMMAND [OPTIONS]\n\nSubcommands:\n");
  for (const auto& s : bead::tools::kSubcommands) std::printf("  %-10s %s\n", s.name, s.summary);
  std::printf(
      "\nUnits: mm, s, mm^2, mm^3/s, RPM, V. File formats: docs/data-formats.md (installed: PREFIX/share/doc/bead;\n"
      "testdata/: PREFIX/share/bead/testdata; man bead-SUBCOMMAND).\n"
      "Example:\n"
      "  bead simulate testdata/configs/sample.yaml -o /tmp/run\n"
      "  bead measure --rig /tmp/run/rig.yaml /tmp/run/run.h5 -o geometry.csv\n"
      "  bead calibrate offset --rig /tmp/run/rig.yaml /tmp/run/pins.h5\n"
      "  bead flow --rig /tmp/run/rig.yaml /tmp/run/run.h5 -o flow.csv\n"
      "  bead batch --rig rig.yaml -o results runs/*.h5 (many runs: resumable, shardable)\n"
      "  bead import VENDOR.csv -o run.h5 --profile-column ... (a profiler's CSV, .mat, PLY, PCD)\n"
      "  bead export --rig /tmp/run/rig.yaml /tmp/run/run.h5 -o run.ply (a point cloud)\n"
      "  bead frames --plane plane.yaml --rate-hz 200 frames/*.png -o run.h5 (camera frames)\n"
      "  bead report --rig /tmp/run/rig.yaml /tmp/run/run.h5 --pins /tmp/run/pins.h5 -o report.html\n"
      "Run 'bead SUBCOMMAND --help' for each subcommand's inputs and outputs; 'bead --version' for the version.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    PrintHelp();
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::printf("bead %s\n", BEAD_VERSION);
    return 0;
  }
  const char* name = argv[1];
  if (*bead::tools::Summary(name) == '\0') {
    std::fprintf(stderr, "bead: error: '%s' is not a subcommand (one of:", name);
    for (const auto& s : bead::tools::kSubcommands) std::fprintf(stderr, " %s", s.name);
    std::fprintf(stderr, "); see bead --help\n");
    return 2;
  }
  const std::string program = bead::tools::OwnFolder(argv[0]) + "/bead-" + name;
  std::vector<char*> args(argv, argv + argc);
  args[0] = const_cast<char*>("bead");
  args.push_back(nullptr);
  execv(program.c_str(), args.data());
  std::fprintf(stderr, "bead: error: %s: cannot run the '%s' subcommand's program (%s): is libbead fully installed?\n",
               program.c_str(), name, std::strerror(errno));
  return 1;
}
