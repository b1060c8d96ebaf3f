#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calibration/reference_areas.h"
#include "tools/rig_input.h"
#include "libbead/archive/open_run.h"
#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"

namespace bead::tools {

namespace {

// The areas proposed, and how clear the rig file's own are.
void PrintAreas(const calibration::ReferenceSurvey& s, const calibration::ReferenceSurveyor& surveyor,
                const RigFile& file, const std::string& rig_path) {
  std::printf("%-8s %10s %10s %10s %10s %10s\n", "area", "x_min", "x_max", "width", "points", "clear");
  std::printf("%-8s %10s %10s %10s %10s %10s\n", "", "mm", "mm", "mm", "/profile", "%");
  for (const auto& [name, a] : {std::pair{"left", s.left}, std::pair{"right", s.right}})
    std::printf("%-8s %10.2f %10.2f %10.2f %10.1f %10.2f\n", name, a.area.x_min_mm, a.area.x_max_mm,
                a.area.x_max_mm - a.area.x_min_mm, a.points_per_profile, 100.0 * a.clear_fraction);
  if (file.has_reference_areas) {
    const Rig& r = file.rig;
    const double cl = surveyor.ClearFraction(r.reference_left), cr = surveyor.ClearFraction(r.reference_right);
    std::printf("the rig file's areas: left [%.2f, %.2f] clear %.2f %%, right [%.2f, %.2f] clear %.2f %%\n",
                r.reference_left.x_min_mm, r.reference_left.x_max_mm, 100.0 * cl, r.reference_right.x_min_mm,
                r.reference_right.x_max_mm, 100.0 * cr);
    if (std::min(cl, cr) < 0.99)
      std::printf(
          "warning: %s: something stands up in the rig file's areas in over 1 %% of the profiles: their "
          "reference line is pulled up there; consider -o\n",
          rig_path.c_str());
  } else {
    std::printf("the rig file has no reference areas\n");
  }
}

}  // namespace

Run AddCalibrateReference(CLI::App* cal) {
  struct Args {
    std::string rig, run, output;
    calibration::ReferenceSurveyOptions options;
    std::size_t max_profiles = 20000;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = cal->add_subcommand("reference", "Reference areas (bare surface either side of the bead) from a run");
  cmd->footer(
      "In:  RIG.yaml (its reference areas may be missing: they are what this proposes) and RUN.h5 or\n"
      "     RUN.csv, a run with the bead on the wheel, the longer the better.\n"
      "Out: each profile's surface line is fitted robustly over the whole profile; points above it by\n"
      "     more than max(--threshold-mm, 6 x the line's RMS) stand up. The bead is the widest such\n"
      "     run; each area starts --margin-mm beyond the bead's outermost edge over the run (its\n"
      "     0.1 % quantile) and grows outward while the surface holds data in 90 % of profiles and\n"
      "     stands up in at most 0.5 % (it stops at the field's end, a rim, a clamp). A table of the\n"
      "     two areas (extent, points per profile, how much of the run each stays clear of anything\n"
      "     standing up), the rig file's own areas against the same, then the line\n"
      "       reference_left_mm=<a>,<b> reference_right_mm=<c>,<d> clear_left=<%> clear_right=<%>\n"
      "     With -o, a copy of the rig file with sensor.reference_areas_mm set, written atomically.\n"
      "Example:\n"
      "  bead calibrate reference --rig rig.yaml run.h5 -o rig-areas.yaml");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5) or profiles CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Rig file to write with the proposed areas");
  cmd->add_option("--margin-mm", args->options.margin_mm, "From the bead's outermost edge to an area, mm")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threshold-mm", args->options.threshold_mm, "Least height that stands up, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-profiles", args->max_profiles, "Profiles surveyed at most (spread evenly over the run)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{100}, std::size_t{100000000}));
  return [args]() {
    RigFile file = ReadRigFileSaying(args->rig, /*areas_required=*/false);
    WorkerPool pool;
    OpenedRun opened = OpenRun(args->run, pool, /*with_log=*/false);
    ProfileStream& stream = *opened.profiles;
    const std::size_t n = stream.size();
    calibration::ReferenceSurveyor surveyor(args->options);
    const std::size_t stride = calibration::SurveyStream(stream, args->max_profiles, surveyor);
    calibration::ReferenceSurvey s;
    try {
      s = surveyor.Propose();
    } catch (const Error& e) {
      throw Error(Located(args->run, "", e.what()));
    }
    std::printf("%s: %zu profiles, %zu surveyed (every %zu), %zu with a surface line, %zu with a bead\n",
                args->run.c_str(), n, s.profiles, stride, s.with_line, s.with_bead);
    std::printf("field x %.2f .. %.2f mm, %.3f mm between points\n", s.field_min_mm, s.field_max_mm, s.spacing_mm);
    std::printf(
        "bead edges over the run: left %.2f mm (median %.2f), right %.2f mm (median %.2f); outermost = the "
        "0.1 %% quantile\n",
        s.bead_left_mm[0], s.bead_left_mm[1], s.bead_right_mm[0], s.bead_right_mm[1]);
    // To 0.01 mm, rounded away from the bead: printed as written.
    s.left.area = {std::ceil(s.left.area.x_min_mm * 100.0) / 100.0, std::floor(s.left.area.x_max_mm * 100.0) / 100.0};
    s.right.area = {std::ceil(s.right.area.x_min_mm * 100.0) / 100.0,
                    std::floor(s.right.area.x_max_mm * 100.0) / 100.0};
    PrintAreas(s, surveyor, file, args->rig);
    if (!args->output.empty()) {
      file.rig.reference_left = s.left.area;
      file.rig.reference_right = s.right.area;
      WriteRigFile(args->output, file);
      std::printf("wrote %s with sensor.reference_areas_mm = [[%.2f, %.2f], [%.2f, %.2f]]\n", args->output.c_str(),
                  s.left.area.x_min_mm, s.left.area.x_max_mm, s.right.area.x_min_mm, s.right.area.x_max_mm);
    }
    std::printf("reference_left_mm=%.2f,%.2f reference_right_mm=%.2f,%.2f clear_left=%.2f%% clear_right=%.2f%%\n",
                s.left.area.x_min_mm, s.left.area.x_max_mm, s.right.area.x_min_mm, s.right.area.x_max_mm,
                100.0 * s.left.clear_fraction, 100.0 * s.right.clear_fraction);
    return 0;
  };
}

}  // namespace bead::tools
