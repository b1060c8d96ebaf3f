#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <unistd.h>

#include "libbead/core/error.h"
#include "libbead/io/run_archive.h"
#include "libbead/vision/frame_profile.h"
#include "libbead/vision/laser_plane_yaml.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddFrames(CLI::App& app) {
  struct Args {
    std::string plane, output;
    std::vector<std::string> frames;
    double rate_hz = 0.0;
    vision::StripeOptions stripe;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("frames", Summary("frames"));
  cmd->footer(
      "In:  PLANE.yaml (where the camera sees the laser plane: points: [[u, v, x_mm, z_mm], ...],\n"
      "     four or more pixel -> plane pairs from a target in the laser's light) and the frames,\n"
      "     in time order (images OpenCV reads: PNG, TIFF, ...; undistorted; colour is made grey).\n"
      "Out: RUN.h5, the run archive of docs/data-formats.md (profiles only): one profile\n"
      "     a frame, one point an image column (the stripe's sub-pixel centre on the laser plane,\n"
      "     NaN where a column has no stripe), frame k at k / rate. No encoder: /profiles/encoder\n"
      "     holds 0 and the root attribute encoder=absent says so (`bead flow` refuses it).\n"
      "Example:\n"
      "  bead frames --plane plane.yaml --rate-hz 200 frames/*.png -o run.h5\n"
      "  bead measure --rig rig.yaml run.h5 -o geometry.csv");
  cmd->add_option("--plane", args->plane, "Laser plane file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("frames", args->frames, "Frames, in time order")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Run archive to write (.h5, written atomically)")->required();
  cmd->add_option("--rate-hz", args->rate_hz, "Frames per second (the profiles' time)")
      ->required()->check(CLI::PositiveNumber);
  cmd->add_option("--min-peak", args->stripe.min_peak, "Least stripe brightness above the column's background, grey levels")
      ->capture_default_str()->check(CLI::PositiveNumber);

  return [args]() {
    const vision::LaserPlaneMap map = vision::ReadLaserPlaneYaml(args->plane);
    RunArchive run;
    ProfileBlock& b = run.profiles;
    b.shared_x = false;
    const bool tty = isatty(STDERR_FILENO);
    std::vector<float> x, z;
    std::size_t columns = 0, points = 0;
    for (std::size_t k = 0; k < args->frames.size(); ++k) {
      const std::string& path = args->frames[k];
      cv::Mat frame = cv::imread(path, cv::IMREAD_UNCHANGED);
      if (frame.empty()) throw Error(Located(path, "", "not an image OpenCV can read"));
      if (frame.channels() == 3) cv::cvtColor(frame, frame, cv::COLOR_BGR2GRAY);
      if (frame.channels() == 4) cv::cvtColor(frame, frame, cv::COLOR_BGRA2GRAY);
      try {
        vision::FrameProfile(frame, map, args->stripe, x, z);
      } catch (const Error& e) {
        throw Error(Located(path, "", e.what()));
      }
      if (k == 0) columns = x.size(), b.points = columns;
      if (x.size() != columns)
        throw Error(Located(path, "", std::to_string(x.size()) + " columns, the first frame has " +
                                          std::to_string(columns) + ": frames of one run share a size"));
      for (float v : z) points += v == v;
      b.t_s.push_back(static_cast<double>(k) / args->rate_hz);
      b.encoder.push_back(0);
      b.x_mm.insert(b.x_mm.end(), x.begin(), x.end());
      b.z_mm.insert(b.z_mm.end(), z.begin(), z.end());
      if (tty) std::fprintf(stderr, "\rread %zu / %zu frames", k + 1, args->frames.size());
    }
    if (tty) std::fprintf(stderr, "\n");
    run.attributes[kEncoderAttribute] = kEncoderAbsent;
    run.attributes["laser_plane"] = std::filesystem::path(args->plane).filename().string();
    WriteRunArchive(args->output, run);  // validates the block
    std::printf("%zu frames of %zu columns: %zu stripe points (%.1f %%); wrote %s\n", b.size(), columns, points,
                100.0 * static_cast<double>(points) / static_cast<double>(b.size() * columns), args->output.c_str());
    return 0;
  };
}

}  // namespace bead::tools
