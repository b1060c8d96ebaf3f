#include <cstdio>
#include <filesystem>
#include <limits>
#include <unistd.h>

#include "libbead/core/error.h"
#include "libbead/io/run_archive.h"
#include "libbead/vision/frame_profile.h"
#include "libbead/vision/laser_plane_yaml.h"
#include "libbead/vision/sensor_yaml.h"
#include "tools/commands.h"
#include "libbead/vision/frames_run.h"
#include "tools/stripe_options.h"
#include "tools/subcommands.h"
#include "tools/tty_progress.h"

namespace bead::tools {

Run AddFrames(CLI::App& app) {
  struct Args {
    std::string plane, sensor, output;
    std::vector<std::string> frames;
    double rate_hz = 0.0;
    StripeFlags stripe;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("frames", Summary("frames"));
  cmd->footer(
      "In:  the sensor: --sensor sensor.yaml (from `bead calibrate laser`: lens model, laser plane,\n"
      "     stripe settings), or --plane plane.yaml (points: [[u, v, x_mm, z_mm], ...], four or more\n"
      "     pixel -> plane pairs from a target in the laser's light; frames already undistorted);\n"
      "     and the frames, in time order (images OpenCV reads: PNG, TIFF, ...; colour is made grey).\n"
      "Out: RUN.h5, the run archive of docs/data-formats.md (profiles only): one profile a frame,\n"
      "     one point per image line across the stripe (per column when it runs along the rows,\n"
      "     per row when it runs down the columns): the stripe's sub-pixel centre, undistorted,\n"
      "     on the laser plane; NaN where a line has no stripe. Frame k at k / rate. No encoder:\n"
      "     /profiles/encoder holds 0 and the root attribute encoder=absent says so.\n"
      "     The stripe flags override the sensor file's; with auto, the first frame decides the axis.\n"
      "     The last line counts what became of the lines searched (found, no peak, too wide, ...).\n"
      "Example:\n"
      "  bead frames --sensor sensor.yaml --rate-hz 200 frames/*.png -o run.h5\n"
      "  bead measure --rig rig.yaml run.h5 -o geometry.csv");
  auto* plane =
      cmd->add_option("--plane", args->plane, "Laser plane file of point pairs (YAML)")->check(CLI::ExistingFile);
  auto* sensor = cmd->add_option("--sensor", args->sensor, "Sensor file from `bead calibrate laser` (YAML)")
                     ->check(CLI::ExistingFile);
  plane->excludes(sensor);
  cmd->add_option("frames", args->frames, "Frames, in time order")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Run archive to write (.h5, written atomically)")->required();
  cmd->add_option("--rate-hz", args->rate_hz, "Frames per second (the profiles' time)")
      ->required()
      ->check(CLI::PositiveNumber);
  AddStripeFlags(cmd, args->stripe);

  return [args]() {
    if (args->plane.empty() && args->sensor.empty())
      throw Error("frames: give the sensor: --sensor sensor.yaml (bead calibrate laser) or --plane plane.yaml");
    vision::SensorModel sensor;
    if (!args->sensor.empty()) {
      sensor = vision::ReadSensorYaml(args->sensor);
    } else {
      sensor.map = vision::ReadLaserPlaneYaml(args->plane);
    }
    sensor.stripe = ApplyStripeFlags(args->stripe, sensor.stripe);
    const auto tty = TtyProgress("read", "frames");
    vision::FramesRun f =
        vision::RunFromFrames(args->frames, sensor, args->rate_hz, [&tty](std::size_t k, std::size_t n) {
          if (tty) tty(k, n);
        });
    f.run.attributes[args->sensor.empty() ? "laser_plane" : "sensor"] =
        std::filesystem::path(args->sensor.empty() ? args->plane : args->sensor).filename().string();
    WriteRunArchive(args->output, f.run);  // validates the block
    std::printf("stripe: axis %s (one point per %s), method %s; %s\n", vision::Name(f.stripe.axis).c_str(),
                f.stripe.axis == vision::StripeAxis::kRows ? "column" : "row", vision::Name(f.stripe.method).c_str(),
                vision::Describe(f.total).c_str());
    const std::size_t frames = f.run.profiles.size();
    std::printf("%zu frames of %zu lines: %zu stripe points (%.1f %%); wrote %s\n", frames, f.lines, f.points,
                100.0 * static_cast<double>(f.points) / static_cast<double>(frames * f.lines), args->output.c_str());
    if (f.points == 0)
      std::printf(
          "warning: no stripe point in any frame: see the counts above (--min-peak, --threshold, "
          "--max-width-px, --stripe-axis)\n");
    return 0;
  };
}

}  // namespace bead::tools
