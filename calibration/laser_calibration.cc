#include "calibration/laser_calibration.h"

#include <opencv2/calib3d.hpp>

#include <cmath>

#include "libbead/core/error.h"

namespace bead::calibration {
namespace {

// The stripe's points of one view on its board plane, camera coordinates:
// the undistorted ray through each centre, met with the plane n . X = n . t
// (n the board's z axis, t its origin, in camera coordinates).
// Points farther than margin_mm outside the inner corners' rectangle
// (extent, mm) are left out and counted in `beyond`.
std::vector<cv::Point3d> Lift(const vision::StripeCentres& stripe, const vision::CameraModel& camera,
                              const cv::Vec3d& rvec, const cv::Vec3d& tvec, cv::Size2d extent, double margin_mm,
                              int& beyond) {
  std::vector<cv::Point2d> px;
  for (std::size_t k = 0; k < stripe.centres.size(); ++k)
    if (!std::isnan(stripe.centres[k])) px.push_back(stripe.Pixel(k));
  std::vector<cv::Point3d> out;
  if (px.empty()) return out;
  std::vector<cv::Point2d> normalised;
  cv::undistortPoints(px, normalised, camera.matrix, camera.distortion, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  const cv::Vec3d n(r(0, 2), r(1, 2), r(2, 2));
  const double nt = n.dot(tvec);
  for (const cv::Point2d& q : normalised) {
    const cv::Vec3d ray(q.x, q.y, 1.0);
    const double along = n.dot(ray);
    if (!(std::abs(along) > 1e-9)) continue;  // a ray parallel to the board
    const double lambda = nt / along;
    if (!(lambda > 0.0)) continue;
    const cv::Vec3d p = lambda * ray;
    const cv::Vec3d b = r.t() * (p - tvec);  // on the board, mm from its first inner corner
    if (b[0] < -margin_mm || b[1] < -margin_mm || b[0] > extent.width + margin_mm || b[1] > extent.height + margin_mm) {
      ++beyond;
      continue;
    }
    out.emplace_back(p[0], p[1], p[2]);
  }
  return out;
}

double AngleDeg(const cv::Vec3d& a, const cv::Vec3d& b) {
  return std::acos(std::clamp(std::abs(a.dot(b)) / (cv::norm(a) * cv::norm(b)), 0.0, 1.0)) * 180.0 / M_PI;
}

// Every image's board corners; the views with a board found.
std::vector<std::size_t> FindBoards(const std::vector<cv::Mat>& frames, const std::vector<std::string>& names,
                                    const Board& board, LaserCalibration& out,
                                    std::vector<std::vector<cv::Point2f>>& corners) {
  std::vector<std::size_t> with_board;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    out.views[i].name = names[i];
    if (frames[i].size() != frames[0].size())
      throw Error(names[i] + ": " + std::to_string(frames[i].cols) + " x " + std::to_string(frames[i].rows) +
                  " px, the first image is " + std::to_string(frames[0].cols) + " x " + std::to_string(frames[0].rows) +
                  ": one camera's images share a size");
    std::vector<cv::Point2f> c = FindBoard(frames[i], board);
    if (c.empty()) continue;
    out.views[i].board = true;
    corners.push_back(std::move(c));
    with_board.push_back(i);
  }
  return with_board;
}

// The stripe in every view with a board, on one axis for all (auto: the
// one found on more lines), lifted onto the board's plane: the points and
// the view each came from.
struct Lifted {
  std::vector<cv::Point3d> points;
  std::vector<std::size_t> view_of;
};
Lifted LiftStripes(const std::vector<cv::Mat>& frames, const std::vector<std::size_t>& with_board, const Board& board,
                   const LaserCalibrationOptions& options, LaserCalibration& out) {
  vision::StripeOptions stripe = options.stripe;
  std::vector<vision::StripeCentres> stripes(with_board.size());
  if (stripe.axis == vision::StripeAxis::kAuto) {
    long rows = 0, columns = 0;
    for (std::size_t j = 0; j < with_board.size(); ++j) {
      vision::FindStripe(frames[with_board[j]], stripe, stripes[j]);
      (stripes[j].axis == vision::StripeAxis::kRows ? rows : columns) += stripes[j].stats.found;
    }
    stripe.axis = columns > rows ? vision::StripeAxis::kColumns : vision::StripeAxis::kRows;
  }
  out.sensor.stripe = stripe;
  Lifted l;
  const cv::Size inner = board.InnerCorners();
  const cv::Size2d extent((inner.width - 1) * board.square_mm, (inner.height - 1) * board.square_mm);
  for (std::size_t j = 0; j < with_board.size(); ++j) {
    if (stripes[j].axis != stripe.axis || options.stripe.axis != vision::StripeAxis::kAuto)
      vision::FindStripe(frames[with_board[j]], stripe, stripes[j]);
    LaserView& v = out.views[with_board[j]];
    v.reprojection_rms_px = out.camera.view_rms_px[j];
    v.stripe = stripes[j].stats;
    for (const cv::Point3d& p : Lift(stripes[j], out.sensor.camera, out.camera.rvecs[j], out.camera.tvecs[j], extent,
                                     options.board_margin_mm, v.beyond_margin))
      l.points.push_back(p), l.view_of.push_back(with_board[j]);
  }
  return l;
}

// Each view's part in the common plane (its points' RMS and mean off it,
// and with more than two views the plane fitted without it); returns the
// inliers' centroid.
cv::Point3d ViewsInThePlane(const Lifted& l, const std::vector<std::size_t>& with_board, LaserCalibration& out) {
  const cv::Vec4d& plane = out.plane.plane;
  std::vector<double> ss(out.views.size(), 0.0), sum(out.views.size(), 0.0);
  cv::Point3d centroid(0, 0, 0);
  for (std::size_t i = 0; i < l.points.size(); ++i) {
    LaserView& v = out.views[l.view_of[i]];
    if (!out.plane.inlier[i]) {
      ++v.outliers;
      continue;
    }
    const double r = Distance(plane, l.points[i]);
    ++v.plane_points, ss[l.view_of[i]] += r * r, sum[l.view_of[i]] += r;
    centroid += l.points[i];
  }
  centroid *= 1.0 / out.plane.inliers;
  for (std::size_t i : with_board) {
    LaserView& v = out.views[i];
    if (v.plane_points == 0) continue;
    ++out.images_used;
    v.plane_rms_mm = std::sqrt(ss[i] / v.plane_points);
    v.plane_mean_mm = sum[i] / v.plane_points;
  }
  if (out.images_used < 2)
    throw Error("the stripe lies on the board's plane in " + std::to_string(out.images_used) +
                " view(s): the laser plane needs the stripe on boards at two or more poses");
  const cv::Vec3d n(plane[0], plane[1], plane[2]);
  if (out.images_used > 2)
    for (std::size_t i : with_board) {
      LaserView& v = out.views[i];
      if (v.plane_points == 0) continue;
      std::vector<cv::Point3d> rest;
      for (std::size_t k = 0; k < l.points.size(); ++k)
        if (l.view_of[k] != i) rest.push_back(l.points[k]);
      const cv::Vec4d p = FitPlaneRobust(rest).plane;
      v.loo_angle_deg = AngleDeg(n, cv::Vec3d(p[0], p[1], p[2]));
      v.loo_offset_mm = std::abs(Distance(p, centroid));
    }
  return centroid;
}

// Coordinates on the plane: z toward the camera along the boards' normal,
// x across it along the stripe's lines; the homography from pixels to them.
cv::Matx33d PlaneMap(const LaserCalibration& out, std::size_t views, const cv::Point3d& centroid) {
  const cv::Vec4d& plane = out.plane.plane;
  const cv::Vec3d n(plane[0], plane[1], plane[2]);
  cv::Vec3d up(0, 0, 0);
  for (std::size_t j = 0; j < views; ++j) {
    cv::Matx33d r;
    cv::Rodrigues(out.camera.rvecs[j], r);
    cv::Vec3d z(r(0, 2), r(1, 2), r(2, 2));
    if (z.dot(out.camera.tvecs[j]) > 0.0) z = -z;  // toward the camera, which sits at the origin
    up += z;
  }
  cv::Vec3d e_z = up - up.dot(n) * n;
  if (cv::norm(e_z) < 0.1 * cv::norm(up)) {  // a laser plane nearly parallel to the boards
    const cv::Vec3d to_camera = -cv::Vec3d(centroid);
    e_z = to_camera - to_camera.dot(n) * n;
  }
  e_z = cv::normalize(e_z);
  cv::Vec3d e_x = cv::normalize(n.cross(e_z));
  const cv::Vec3d along =
      out.sensor.stripe.axis == vision::StripeAxis::kColumns ? cv::Vec3d(0, 1, 0) : cv::Vec3d(1, 0, 0);
  if (e_x.dot(along) < 0.0) e_x = -e_x;
  const cv::Vec3d origin = cv::Vec3d(centroid) - Distance(plane, centroid) * n;
  return PlaneHomography(out.sensor.camera.matrix, plane, origin, e_x, e_z);
}

}  // namespace

LaserCalibration CalibrateLaser(const std::vector<cv::Mat>& frames, const std::vector<std::string>& names,
                                const Board& board, const LaserCalibrationOptions& options) {
  LaserCalibration out;
  out.views.resize(frames.size());
  std::vector<std::vector<cv::Point2f>> corners;
  const std::vector<std::size_t> with_board = FindBoards(frames, names, board, out, corners);
  out.camera = FitCamera(board, corners, frames.at(0).size(), options.lens);
  out.sensor.camera = out.camera.camera;
  const Lifted lifted = LiftStripes(frames, with_board, board, options, out);
  out.plane = FitPlaneRobust(lifted.points);
  if (out.plane.inliers < 10)
    throw Error("only " + std::to_string(out.plane.inliers) + " of " + std::to_string(lifted.points.size()) +
                " stripe points agree on one plane: the stripe is not on the boards (see --stripe-axis, "
                "--board-margin-mm)");
  out.sensor.plane = out.plane.plane;
  const cv::Point3d centroid = ViewsInThePlane(lifted, with_board, out);
  out.sensor.map.mm_from_px = PlaneMap(out, with_board.size(), centroid);
  return out;
}

}  // namespace bead::calibration
