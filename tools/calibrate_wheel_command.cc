#include <cmath>
#include <cstdio>

#include "calibration/wheel_runout.h"
#include "tools/rig_input.h"
#include "libbead/archive/measured_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/series/encoder.h"
#include "tools/commands.h"

namespace bead::tools {

Run AddCalibrateWheel(CLI::App* cal) {
  struct Args {
    std::string rig, run, output;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = cal->add_subcommand("wheel", "The wheel's runout and eccentricity from a run's reference line");
  cmd->footer(
      "In:  RIG.yaml and RUN.h5 (a run over one or more whole turns of the wheel; several are better).\n"
      "Out: the reference line's height at the laser against the wheel's encoder angle, fitted with\n"
      "     once- and twice-per-revolution terms and a slow cubic drift; a table of the terms with\n"
      "     95 % intervals, then the line\n"
      "       runout_mm=<v> eccentricity_mm=<v> phase_deg=<v>\n"
      "     runout: peak to peak of the once + twice curve (a dial indicator's reading);\n"
      "     eccentricity: the once-per-revolution amplitude e; phase: the encoder angle (counts\n"
      "     modulo a revolution, of the raw counter) at which the surface at the laser is highest.\n"
      "     The wheel point at the laser carried that material under the nozzle at its own radius,\n"
      "     so `bead flow` multiplies the surface speed by 1 + e cos(angle - phase) / R.\n"
      "     With -o, a copy of the rig file with wheel.eccentricity_mm and\n"
      "     wheel.eccentricity_phase_deg (docs/data-formats.md), written atomically. The phase holds\n"
      "     while the encoder counter keeps its zero: calibrate again after a counter reset.\n"
      "Example:\n"
      "  bead calibrate wheel --rig rig.yaml run.h5 -o rig-wheel.yaml");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Rig file to write with the wheel's eccentricity");
  return [args]() {
    RigFile file = ReadRigFileSaying(args->rig);
    Rig rig = file.rig;
    WorkerPool pool;
    OpenedRun opened = OpenRun(args->run, pool);
    RequireMotion(opened.run, args->run, "the wheel's runout");
    MeasureRunOptions measure;
    measure.occlusion = OcclusionMode::kNone;
    const MeasuredRun m = MeasureWholeRun(std::move(opened), rig, pool, measure);
    const ProfileBlock& b = m.run.profiles;
    const EncoderTrack track = UnwrapEncoder(b.encoder, rig.encoder, b.t_s);
    // The reference line's height midway between the reference areas.
    const double x = 0.25 * (rig.reference_left.x_min_mm + rig.reference_left.x_max_mm + rig.reference_right.x_min_mm +
                             rig.reference_right.x_max_mm);
    std::vector<double> height(b.size(), NAN);
    for (std::size_t k = 0; k < b.size(); ++k) {
      const ReferenceLine& l = m.geometry[k].reference;
      if (l.ok) height[k] = l.intercept_mm + l.slope * x;
    }
    calibration::WheelRunout w;
    try {
      w = calibration::FitWheelRunout(rig, b.t_s, track.counts, height);
    } catch (const Error& e) {
      throw Error(Located(args->run, "", e.what()));
    }
    std::printf("%s: %d profiles with a reference line over %.2f turns of the wheel\n", args->run.c_str(),
                w.profiles_used, w.turns);
    std::printf("%-22s %12s %12s %12s\n", "term", "amplitude", "ci95", "phase");
    std::printf("%-22s %12s %12s %12s\n", "", "mm", "mm", "deg");
    std::printf("%-22s %12.4f %12.4f %8.1f +- %.1f\n", "once per revolution", w.eccentricity_mm, w.eccentricity_ci95_mm,
                w.phase_deg, w.phase_ci95_deg);
    std::printf("%-22s %12.4f %12.4f %12.1f\n", "twice per revolution", w.twice_mm, w.twice_ci95_mm, w.twice_phase_deg);
    std::printf("drift over the run %.4f mm; residual %.4f mm RMS (correlated: intervals widened %.1fx in variance)\n",
                w.drift_mm, w.residual_rms_mm, w.inflation);
    const double radius = 0.5 * rig.wheel_diameter_mm;
    std::printf("surface speed under the nozzle varies by +-%.3f %% (e / R)\n", 100.0 * w.eccentricity_mm / radius);
    if (w.eccentricity_mm < w.eccentricity_ci95_mm)
      std::printf(
          "warning: %s: the once-per-revolution term is within its interval of zero: the wheel is centred "
          "as far as this run can tell\n",
          args->run.c_str());
    if (!args->output.empty()) {
      file.rig.wheel_eccentricity_mm = w.eccentricity_mm;
      file.rig.wheel_eccentricity_phase_deg = w.phase_deg;
      WriteRigFile(args->output, file);
      std::printf("wrote %s with wheel.eccentricity_mm = %.4f, wheel.eccentricity_phase_deg = %.1f\n",
                  args->output.c_str(), w.eccentricity_mm, w.phase_deg);
    }
    std::printf("runout_mm=%.4f eccentricity_mm=%.4f phase_deg=%.1f\n", w.runout_mm, w.eccentricity_mm, w.phase_deg);
    return 0;
  };
}

}  // namespace bead::tools
