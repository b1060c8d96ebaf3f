// A camera-and-laser sensor calibrated from frames of a chessboard with
// the laser stripe across it or its margin (`bead calibrate laser`):
//
// 1. the board's corners in each frame, and from them the camera's
//    intrinsics and distortion and each view's board pose (chessboard.h);
// 2. the stripe in each frame where the board was found (stripe.h), each
//    point undistorted and its ray intersected with that view's board
//    plane: points of the laser plane in camera coordinates, mm;
// 3. one plane through the points of all views, robustly (plane_fit.h):
//    points on another surface (the stripe off the board's paper) are
//    outliers, counted per view;
// 4. coordinates on the plane for the profiles: z along the board's
//    normal (averaged over the views, pointing to the camera) projected
//    into the plane, so z is height above the board; x across, growing
//    along the stripe's image lines; origin at the used points' centroid;
//    and the homography from undistorted pixels to (x, z).
// Every view's part is kept for the table: its reprojection RMS, stripe
// points, inliers, and residual RMS and mean against the common plane. A
// leave-one-view-out refit says how much each view moves the plane.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "calibration/chessboard.h"
#include "calibration/plane_fit.h"
#include "libbead/vision/sensor.h"

namespace bead::calibration {

struct LaserView {
  std::string name;
  bool board = false;
  double reprojection_rms_px = 0.0;
  vision::StripeStats stripe;
  int beyond_margin = 0;  // stripe points farther from the board than the margin, left out
  int plane_points = 0;   // the view's stripe points within the common plane's inlier band
  int outliers = 0;
  double plane_rms_mm = 0.0;   // of its inliers' distances to the common plane
  double plane_mean_mm = 0.0;  // their mean: a view whose board pose is off sits to one side
  double loo_angle_deg = 0.0;  // how far the plane's normal turns without this view
  double loo_offset_mm = 0.0;  // and how far it moves at the points' centroid
};

struct LaserCalibration {
  vision::SensorModel sensor;
  CameraFit camera;
  PlaneFit plane;
  std::vector<LaserView> views;
  int images_used = 0;  // the board found and stripe points on it
};

struct LaserCalibrationOptions {
  vision::StripeOptions stripe;
  LensTerms lens = LensTerms::kK1K2P;
  // Stripe points farther than this outside the board's inner corners
  // are not used: the board's plane holds only as far as its plate (and
  // a thin sheet may lift). Infinite: the whole stripe, outliers left to
  // the robust fit.
  double board_margin_mm = std::numeric_limits<double>::infinity();
};

// frames: one channel, 8- or 16-bit, all the same size; names label them.
// Throws bead::Error when too few views have the board or the stripe.
LaserCalibration CalibrateLaser(const std::vector<cv::Mat>& frames, const std::vector<std::string>& names,
                                const Board& board, const LaserCalibrationOptions& options);

}  // namespace bead::calibration
