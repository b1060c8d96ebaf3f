#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <unistd.h>

#include "calibration/laser_calibration.h"
#include "libbead/core/error.h"
#include "libbead/vision/sensor_yaml.h"
#include "tools/commands.h"
#include "libbead/vision/grey_frame.h"
#include "tools/stripe_options.h"

namespace bead::tools {

namespace {

// The table of the images, and a warning when they disagree on the plane.
void PrintViews(const calibration::LaserCalibration& c, const calibration::Board& board) {
  std::printf("%-28s %5s %8s %9s %6s %7s %5s %8s %8s %7s %8s\n", "image", "board", "reproj", "stripe", "beyond",
              "plane", "off", "rms", "mean", "loo", "loo");
  std::printf("%-28s %5s %8s %9s %6s %7s %5s %8s %8s %7s %8s\n", "", "", "px", "lines", "margin", "points", "", "mm",
              "mm", "deg", "mm");
  for (const calibration::LaserView& v : c.views) {
    std::string name = v.name.size() > 28 ? "..." + v.name.substr(v.name.size() - 25) : v.name;
    if (!v.board) {
      std::printf("%-28s %5s  (the board's %dx%d inner corners were not found)\n", name.c_str(), "no",
                  board.InnerCorners().width, board.InnerCorners().height);
      continue;
    }
    std::printf("%-28s %5s %8.3f %4d/%-4d %6d %7d %5d %8.4f %8.4f %7.3f %8.3f\n", name.c_str(), "yes",
                v.reprojection_rms_px, v.stripe.found, v.stripe.lines, v.beyond_margin, v.plane_points, v.outliers,
                v.plane_rms_mm, v.plane_mean_mm, v.loo_angle_deg, v.loo_offset_mm);
  }
  double lo = 1e300, hi = -1e300;
  for (const calibration::LaserView& v : c.views)
    if (v.plane_points > 0) lo = std::min(lo, v.plane_mean_mm), hi = std::max(hi, v.plane_mean_mm);
  if (hi - lo > 2.0 * c.plane.sigma_mm && hi - lo > 0.05)
    std::printf(
        "warning: the images disagree: their mean distances from the plane span %.3f to %.3f mm against a "
        "spread of %.3f mm within them; the board's plane may not hold where the stripe falls (the edge "
        "of its plate, a lifted sheet) or the lens is poorly determined; compare --board-margin-mm 10 and "
        "--lens k1\n",
        lo, hi, c.plane.sigma_mm);
}

// The camera and lens terms with their standard deviations, the plane, the stripe.
void PrintCameraAndPlane(const calibration::LaserCalibration& c, const std::string& lens) {
  const auto& k = c.sensor.camera.matrix;
  const auto& d = c.sensor.camera.distortion;
  const auto& sd = c.camera.sd;
  std::printf("camera: fx %.1f +- %.1f px, fy %.1f +- %.1f px, cx %.1f +- %.1f px, cy %.1f +- %.1f px (1 sigma)\n",
              k(0, 0), sd[0], k(1, 1), sd[1], k(0, 2), sd[2], k(1, 2), sd[3]);
  std::printf("lens (%s):", lens.c_str());
  const char* names[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) {
    if (sd[static_cast<std::size_t>(4 + i)] > 0.0)
      std::printf(" %s %.5f +- %.5f", names[i], d[static_cast<std::size_t>(i)], sd[static_cast<std::size_t>(4 + i)]);
    else
      std::printf(" %s 0 (held)", names[i]);
  }
  std::printf("\n");
  const cv::Vec4d& p = c.sensor.plane;
  std::printf(
      "laser plane: %.5f x + %.5f y + %.5f z + %.3f = 0 (camera coordinates, mm); "
      "robust spread %.4f mm, %d of %zu points on it\n",
      p[0], p[1], p[2], p[3], c.plane.sigma_mm, c.plane.inliers, c.plane.inlier.size());
  std::printf("stripe: axis %s, method %s\n", vision::Name(c.sensor.stripe.axis).c_str(),
              vision::Name(c.sensor.stripe.method).c_str());
}

}  // namespace

Run AddCalibrateLaser(CLI::App* cal) {
  struct Args {
    std::string board, output;
    double square_mm = 0.0;
    std::string lens = "k1k2p";
    double margin_mm = std::numeric_limits<double>::infinity();
    std::vector<std::string> images;
    StripeFlags stripe;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = cal->add_subcommand("laser", "Camera, lens and laser plane from chessboard images with the stripe");
  cmd->footer(
      "In:  images of a printed chessboard lying flat, the laser stripe across it or its margin, the\n"
      "     board (or the sensor) moved between shots: 3 or more views with the board, at different\n"
      "     tilts; the stripe must fall on the board's paper (its plane is extended beyond the corners).\n"
      "Out: a table of the images (board found, corner reprojection RMS, stripe lines found, points on\n"
      "     the plane and off it, residual RMS and mean against the plane, how far leaving the image\n"
      "     out turns and moves the plane), then the line\n"
      "       reprojection_rms_px=<v> plane_rms_mm=<v> images_used=<n>/<total>\n"
      "     With -o, the sensor file for `bead frames --sensor` (docs/data-formats.md), written\n"
      "     atomically. Profile coordinates: z is height above the board (toward the camera), x runs\n"
      "     along the stripe's image lines, the origin is the stripe points' centroid.\n"
      "     Each fitted camera and lens term is printed with its standard deviation; terms not\n"
      "     fitted (--lens) print as 0 (held).\n"
      "Example:\n"
      "  bead calibrate laser --board 8x7 --square-mm 10 calib/frame*.png -o sensor.yaml");
  cmd->add_option("--board", args->board, "Chessboard as printed: squares along each side, COLSxROWS (e.g. 8x7)")
      ->required();
  cmd->add_option("--square-mm", args->square_mm, "Side of one square, mm")->required()->check(CLI::PositiveNumber);
  cmd->add_option("images", args->images, "Images of the board with the stripe")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Sensor file to write (YAML)");
  cmd->add_option("--lens", args->lens,
                  "Distortion terms fitted (the rest held at 0): k1, k1k2, k1k2p (with tangential p1 p2), full "
                  "(k1 k2 p1 p2 k3); few views determine the higher terms poorly")
      ->capture_default_str();
  cmd->add_option("--board-margin-mm", args->margin_mm,
                  "Use only stripe points within this distance outside the board's inner corners (default: "
                  "all, the points off the board's plane left out by the robust fit)")
      ->check(CLI::NonNegativeNumber);
  AddStripeFlags(cmd, args->stripe);

  return [args]() {
    const calibration::Board board = calibration::ParseBoard(args->board, args->square_mm);
    calibration::LaserCalibrationOptions options;
    options.stripe = ApplyStripeFlags(args->stripe, {});
    options.lens = calibration::ParseLensTerms(args->lens);
    options.board_margin_mm = args->margin_mm;
    std::vector<cv::Mat> frames;
    for (std::size_t k = 0; k < args->images.size(); ++k) {
      cv::Mat f = vision::ReadGreyFrame(args->images[k]);
      if (f.depth() != CV_8U && f.depth() != CV_16U)
        throw Error(Located(args->images[k], "", "expected 8- or 16-bit grey levels for the board search"));
      frames.push_back(f);
    }
    const calibration::LaserCalibration c = calibration::CalibrateLaser(frames, args->images, board, options);
    PrintViews(c, board);
    PrintCameraAndPlane(c, args->lens);
    if (!args->output.empty()) {
      std::ostringstream notes;
      notes.precision(6);
      notes << "{board: " << args->board << ", square_mm: " << args->square_mm
            << ", reprojection_rms_px: " << c.camera.rms_px << ", plane_rms_mm: " << c.plane.rms_mm
            << ", images_used: " << c.images_used << ", images: " << c.views.size() << "}";
      vision::WriteSensorYaml(args->output, c.sensor, notes.str());
      std::printf("wrote %s\n", args->output.c_str());
    }
    std::printf("reprojection_rms_px=%.4f plane_rms_mm=%.4f images_used=%d/%zu\n", c.camera.rms_px, c.plane.rms_mm,
                c.images_used, c.views.size());
    return 0;
  };
}

}  // namespace bead::tools
