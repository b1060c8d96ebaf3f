// bead: the libbead command line. Thin: each subcommand parses its options
// and calls the library. Every error is printed as one line naming the file
// and place, and exits with status 1; usage errors exit with status 2.
#include <cstdio>
#include <exception>
#include <map>

#include "libbead/core/error.h"
#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"bead: bead cross-sections and volumetric flow from laser line profiles (libbead)"};
  app.footer(
      "Units: mm, s, mm^2, mm^3/s, RPM, V. File formats: docs/data-formats.md.\n"
      "Example:\n"
      "  bead simulate testdata/configs/sample.yaml -o /tmp/run\n"
      "  bead measure --rig /tmp/run/rig.yaml /tmp/run/run.h5 -o geometry.csv\n"
      "  bead calibrate offset --rig /tmp/run/rig.yaml /tmp/run/pins.h5\n"
      "  bead flow --rig /tmp/run/rig.yaml /tmp/run/run.h5 -o flow.csv\n"
      "  bead batch --rig rig.yaml -o results runs/*.h5 (many runs: resumable, shardable)\n"
      "  bead import VENDOR.csv -o run.h5 --profile-column ... (a profiler's own CSV export)\n"
      "  bead frames --plane plane.yaml --rate-hz 200 frames/*.png -o run.h5 (camera frames)\n"
      "Run 'bead SUBCOMMAND --help' for each subcommand's inputs and outputs.");
  app.require_subcommand(1);
  std::map<std::string, bead::tools::Run> runs;
  runs["measure"] = bead::tools::AddMeasure(app);
  runs["simulate"] = bead::tools::AddSimulate(app);
  runs["flow"] = bead::tools::AddFlow(app);
  runs["calibrate"] = bead::tools::AddCalibrate(app);
  runs["identify"] = bead::tools::AddIdentify(app);
  runs["explain"] = bead::tools::AddExplain(app);
  runs["import"] = bead::tools::AddImport(app);
  runs["frames"] = bead::tools::AddFrames(app);
  runs["batch"] = bead::tools::AddBatch(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    for (const auto* sub : app.get_subcommands()) return runs.at(sub->get_name())();
  } catch (const bead::Error& e) {
    std::fprintf(stderr, "bead: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bead: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
