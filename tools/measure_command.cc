#include <cstdio>

#include "tools/rig_input.h"
#include "libbead/archive/measure_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/io/geometry_csv.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"
#include "tools/subcommands.h"
#include "tools/tty_progress.h"
#include "tools/part_scan.h"
#include "libbead/io/run_archive.h"
#include "tools/occlusion_module.h"
#include "tools/occlusion_step.h"

namespace bead::tools {

Run AddMeasure(CLI::App& app) {
  struct Args {
    std::string rig, run, output;
    ProfileOptions options;
    unsigned threads = 0;
    std::string occlusion = "pooled";
    std::string beads = "one", laid = "left-first";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("measure", Summary("measure"));
  cmd->footer(
      "In:  RIG.yaml (reference areas) and RUN.h5 (run archive) or RUN.csv (profiles CSV),\n"
      "     as docs/data-formats.md defines them. An archive is read in windows of whole\n"
      "     chunks: memory stays flat whatever the run's length.\n"
      "     A part scan (format 1.1: root attribute kind = \"part\") is measured layer on\n"
      "     layer: each profile against the layer below at its place along the path\n"
      "     (layer 0 against the bed's reference line), the layer below registered\n"
      "     laterally; its rig file needs the reference areas and no wheel. It writes the\n"
      "     part geometry CSV: profile,t_s,layer,path_mm,area_mm2,width_mm,height_mm,\n"
      "     area_corrected_mm2,valid, then center_x_mm, offset_below_mm (wall wander),\n"
      "     shift_mm, shift_sigma_mm, shift_found, registration_rms_mm, noise_mm, status.\n"
      "Out: geometry CSV, one row per profile in order: profile,t_s,encoder,area_mm2,\n"
      "     width_mm,height_mm,area_corrected_mm2,valid, then center_x_mm, reference_rms_mm,\n"
      "     reference_points, threshold_mm, dropped_points, status (why a row is invalid),\n"
      "     area_sigma_mm2, occlusion_bias_mm2, area_corrected_sigma_mm2.\n"
      "     area_corrected_mm2 = area_mm2 - occlusion_bias_mm2: what the sensor could not see\n"
      "     under the bead's widest point and in the fan's shadow (see --occlusion).\n"
      "--beads all: every bead of each profile (roads of one layer, beads welded side by\n"
      "     side), over the bed's reference line (a part scan: layer on layer, the layer below\n"
      "     moved by its registration's shift). Neighbours that overlap are split by the\n"
      "     overlap model: each road's top a cap of the layer's one shape, laid in order\n"
      "     (--laid), each adding to the surface before it, so the later road keeps the\n"
      "     valley's material. The profile cannot show that order (the top is the highest\n"
      "     cap either way): it says how far the areas would move laid the other way.\n"
      "     One row per bead found:\n"
      "     profile,bead,t_s,center_x_mm,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,\n"
      "     then layer, path_mm, spacing_over_width, fit_rms_mm, status; bead counts from 0,\n"
      "     left to right; a bead cut by the field of view's end has valid = 0 and no size.\n"
      "Examples:\n"
      "  bead measure --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o geometry.csv\n"
      "  bead simulate testdata/configs/part_roads.yaml -o roads && \\\n"
      "    bead measure --rig roads/rig.yaml roads/part.h5 --beads all -o beads.csv");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5) or profiles CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Geometry CSV to write (written atomically)")->required();
  auto& o = args->options;
  cmd->add_option("--threshold-mm", o.bead.min_threshold_mm, "Least height that counts as bead, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threshold-sigmas", o.bead.threshold_sigmas,
                  "Threshold in reference-line residual RMS, when larger than --threshold-mm")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--spike-mm", o.bead.spike_mm, "A point this far off its neighbours' median is a spike, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-gap-mm", o.bead.max_gap_mm, "Longest dropout bridged inside a bead, mm")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--beads", args->beads, "one: the largest bead of each profile; all: every bead, one row each")
      ->capture_default_str()
      ->check(CLI::IsMember({"one", "all"}));
  cmd->add_option("--laid", args->laid, "With --beads all: the order the beads were laid in")
      ->capture_default_str()
      ->check(CLI::IsMember({"left-first", "right-first"}));
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")->capture_default_str();
  AddOcclusionOption(cmd, args->occlusion);

  return [args]() {
    if (args->beads == "all")
      return MeasureRoads(args->rig, args->run, args->output, args->options, args->laid == "left-first", args->threads);
    // A part scan (kind = "part") is measured layer on layer.
    if (IsPartScanFile(args->run))
      return MeasurePartScan(args->rig, args->run, args->output, args->options, args->threads);
    const Rig rig = ReadRigSaying(args->rig);
    WorkerPool pool(args->threads);
    OpenedRun opened = OpenRun(args->run, pool, /*with_log=*/false);
    MeasureRunOptions options;
    options.profile = args->options;
    options.occlusion = ParseOcclusionMode(args->occlusion);
    options.estimate = EstimateOcclusionOnDemand;
    options.progress = TtyProgress("measured");
    GeometryCsvWriter out(args->output);
    const MeasureRunSummary s =
        MeasureRun(*opened.profiles, rig, pool, options, [&](const GeometryRow& row) { out.Append(row); });
    out.Commit();
    if (const std::string line = OcclusionLine(s); !line.empty()) std::printf("%s\n", line.c_str());
    std::printf("%s: %zu profiles, %zu valid, measured in %.3f s; wrote %s\n", args->run.c_str(), s.profiles, s.valid,
                s.seconds, args->output.c_str());
    for (std::size_t k = 1; k < s.by_status.size(); ++k)
      if (s.by_status[k]) std::printf("  %zu invalid: %s\n", s.by_status[k], StatusName(static_cast<ProfileStatus>(k)));
    if (s.valid == 0 && s.by_status[static_cast<std::size_t>(ProfileStatus::kNoReference)] > 0)
      std::printf(
          "  no profile has enough points in the reference areas [%g, %g] and [%g, %g] mm: check the rig's\n"
          "  reference_areas_mm against the profiles' x (no area is measured without bare surface)\n",
          rig.reference_left.x_min_mm, rig.reference_left.x_max_mm, rig.reference_right.x_min_mm,
          rig.reference_right.x_max_mm);
    if (EncoderAbsent(opened.run)) std::printf("  the archive has no encoder readings: the encoder column holds 0\n");
    return 0;
  };
}

}  // namespace bead::tools
