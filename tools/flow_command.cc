#include <cstdio>
#include <filesystem>

#include "tools/rig_input.h"
#include "libbead/archive/run_flow.h"
#include "libbead/core/error.h"
#include "libbead/flow/flow.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"
#include "tools/own_folder.h"
#include "tools/subcommands.h"
#include "tools/tty_progress.h"
#include "tools/part_scan.h"
#include "libbead/io/run_archive.h"
#include "tools/occlusion_module.h"
#include "tools/occlusion_step.h"

namespace bead::tools {

Run AddFlow(CLI::App& app) {
  struct Args {
    std::string rig, run, output;
    FlowOptions flow;
    ProfileOptions profile;
    std::string occlusion = "pooled";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("flow", Summary("flow"));
  cmd->footer(
      "In:  RIG.yaml (encoder, wheel, offset, reference areas) and RUN.h5 with /profiles and /log.\n"
      "Out: flow CSV: t_s (when the material left the nozzle), encoder, surface_speed_mm_s,\n"
      "     area_mm2, area_corrected_mm2, flow_mm3_s, screw_rpm, then profile, valid,\n"
      "     occlusion_bias_mm2, area_corrected_sigma_mm2, flow_sigma_mm3_s (see --occlusion).\n"
      "     Prints the run's total volume (mm^3).\n"
      "     A part scan (format 1.1, kind = \"part\"; its log holds layer and path_mm) gives the\n"
      "     flow along the toolpath: t_s (when the nozzle laid each place), layer, path_mm,\n"
      "     head_speed_mm_s, area_mm2, area_corrected_mm2, flow_mm3_s (head speed x area),\n"
      "     screw_rpm, then profile, valid; and the volume each layer added.\n"
      "With no arguments it runs on the bundled sample run (testdata/sample) and says so.\n"
      "Example:\n"
      "  bead flow --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o flow.csv");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5)")->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Flow CSV to write (atomically)");
  cmd->add_option("--speed-window-s", args->flow.speed_window_s, "Savitzky-Golay window of the wheel speed, s")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--area-smooth", args->flow.area_smooth_window,
                  "Odd Savitzky-Golay window on the area, profiles (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  AddOcclusionOption(cmd, args->occlusion);
  return [args]() {
    if (args->rig.empty() && args->run.empty()) {
      const std::string sample = InstalledOr("testdata/sample", std::string(BEAD_SOURCE_DIR) + "/testdata/sample");
      args->rig = sample + "/rig.yaml";
      args->run = sample + "/run.h5";
      if (args->output.empty()) {
        args->output = "flow.csv";
        // The user's own flow.csv is never replaced by the sample's.
        if (std::filesystem::exists(args->output))
          throw CLI::ValidationError("-o", "./flow.csv exists: name the output with -o to write the sample's flow");
      }
      std::printf("no run given: using the bundled sample run %s (written to %s)\n", args->run.c_str(),
                  args->output.c_str());
    }
    if (args->rig.empty() || args->run.empty() || args->output.empty())
      throw CLI::RequiredError("--rig, RUN and -o are all needed (or none, for the bundled sample)");
    // A part scan (kind = "part"): the flow along the toolpath.
    if (IsPartScanFile(args->run)) return FlowPartScan(args->rig, args->run, args->output, args->profile);
    const Rig rig = ReadRigSaying(args->rig);
    WorkerPool pool;
    RunFlowRequest request;
    request.measure.profile = args->profile;
    request.measure.occlusion = ParseOcclusionMode(args->occlusion);
    request.measure.estimate = EstimateOcclusionOnDemand;
    request.measure.progress = TtyProgress("measured");
    request.flow = args->flow;
    request.flow_csv = args->output;
    const RunFlow f = MeasureRunFlow(args->run, rig, pool, request);
    if (!f.whole_run_why.empty())
      std::fprintf(stderr, "note: %s: the flow is computed on the whole run in memory: %s\n", args->run.c_str(),
                   f.whole_run_why.c_str());
    if (const std::string line = OcclusionLine(f.measure); !line.empty()) std::printf("%s\n", line.c_str());
    std::printf("%s: %zu profiles, %zu with flow; %d area outliers, %d speed outliers, %d encoder reads repaired\n",
                args->run.c_str(), f.samples, f.valid, f.area_outliers, f.speed_outliers, f.encoder_repairs);
    for (const std::string& w : f.warnings) std::fprintf(stderr, "warning: %s: %s\n", args->run.c_str(), w.c_str());
    std::printf("total volume: %.1f mm^3 (%s area)\n", f.total_volume_mm3,
                args->occlusion == "none" ? "measured" : "occlusion-corrected");
    std::printf("wrote %s\n", args->output.c_str());
    return 0;
  };
}

}  // namespace bead::tools
