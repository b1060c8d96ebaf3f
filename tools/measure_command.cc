#include <chrono>
#include <cstdio>
#include <unistd.h>

#include "libbead/io/geometry_csv.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/profile/measure_block.h"
#include "tools/commands.h"
#include "tools/load_profiles.h"
#include "tools/occlusion_step.h"

namespace bead::tools {

Run AddMeasure(CLI::App& app) {
  struct Args {
    std::string rig, run, output;
    ProfileOptions options;
    unsigned threads = 0;
    std::string occlusion = "pooled";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("measure", "Bead area, width and height of every profile of a run");
  cmd->footer(
      "In:  RIG.yaml (reference areas) and RUN.h5 (run archive) or RUN.csv (profiles CSV),\n"
      "     as shared/spec/data-formats.md defines them.\n"
      "Out: geometry CSV, one row per profile in order: profile,t_s,encoder,area_mm2,\n"
      "     width_mm,height_mm,area_corrected_mm2,valid, then center_x_mm, reference_rms_mm,\n"
      "     reference_points, threshold_mm, dropped_points, status (why a row is invalid),\n"
      "     area_sigma_mm2, occlusion_bias_mm2, area_corrected_sigma_mm2.\n"
      "     area_corrected_mm2 = area_mm2 - occlusion_bias_mm2: what the sensor could not see\n"
      "     under the bead's widest point and in the fan's shadow (see --occlusion).\n"
      "Example:\n"
      "  bead measure --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o geometry.csv");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5) or profiles CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Geometry CSV to write (written atomically)")->required();
  auto& o = args->options;
  cmd->add_option("--threshold-mm", o.bead.min_threshold_mm, "Least height that counts as bead, mm")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--threshold-sigmas", o.bead.threshold_sigmas,
                  "Threshold in reference-line residual RMS, when larger than --threshold-mm")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--spike-mm", o.bead.spike_mm, "A point this far off its neighbours' median is a spike, mm")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--max-gap-mm", o.bead.max_gap_mm, "Longest dropout bridged inside a bead, mm")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")->capture_default_str();
  AddOcclusionOption(cmd, args->occlusion);

  return [args]() {
    const Rig rig = ReadRig(args->rig);
    const RunArchive run = LoadRun(args->run);
    const auto& block = run.profiles;
    const bool tty = isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    BatchOptions batch;
    batch.threads = args->threads;
    if (tty)
      batch.progress = [](std::size_t done, std::size_t total) {
        std::fprintf(stderr, "\rmeasured %zu / %zu profiles", done, total);
      };
    const std::vector<BeadGeometry> geometry = MeasureProfiles(
        block.size(), [&](std::size_t i) { return block.view(i); }, rig.reference_left, rig.reference_right,
        args->options, batch);
    if (tty) std::fprintf(stderr, "\n");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const OcclusionColumns occ = RunOcclusion(args->occlusion, rig, block, geometry);
    std::vector<GeometryRow> rows(geometry.size());
    std::size_t valid = 0;
    std::vector<std::size_t> by_status(8, 0);
    for (std::size_t i = 0; i < geometry.size(); ++i) {
      rows[i] = GeometryRow{static_cast<int64_t>(i), block.t_s[i],        block.encoder[i],
                            geometry[i],              occ.corrected[i], occ.bias[i], occ.sigma[i]};
      valid += geometry[i].valid();
      ++by_status[static_cast<std::size_t>(geometry[i].status)];
    }
    WriteGeometryCsv(args->output, rows);
    std::printf("%s: %zu profiles, %zu valid, measured in %.3f s; wrote %s\n", args->run.c_str(), rows.size(), valid,
                seconds, args->output.c_str());
    for (std::size_t s = 1; s < by_status.size(); ++s)
      if (by_status[s])
        std::printf("  %zu invalid: %s\n", by_status[s], StatusName(static_cast<ProfileStatus>(s)));
    if (valid == 0 && by_status[static_cast<std::size_t>(ProfileStatus::kNoReference)] > 0)
      std::printf("  no profile has enough points in the reference areas [%g, %g] and [%g, %g] mm: check the rig's\n"
                  "  reference_areas_mm against the profiles' x (no area is measured without bare surface)\n",
                  rig.reference_left.x_min_mm, rig.reference_left.x_max_mm, rig.reference_right.x_min_mm,
                  rig.reference_right.x_max_mm);
    if (EncoderAbsent(run)) std::printf("  the archive has no encoder readings: the encoder column holds 0\n");
    return 0;
  };
}

}  // namespace bead::tools
