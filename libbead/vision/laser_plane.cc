#include "libbead/vision/laser_plane.h"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <string>

#include "libbead/core/error.h"

namespace bead::vision {

LaserPlaneMap FitLaserPlaneMap(const std::vector<cv::Point2d>& px, const std::vector<cv::Point2d>& mm,
                               double max_residual_mm) {
  if (px.size() != mm.size())
    throw Error("laser plane map: " + std::to_string(px.size()) + " pixel points but " + std::to_string(mm.size()) +
                " plane points");
  if (px.size() < 4)
    throw Error("laser plane map: " + std::to_string(px.size()) + " point pairs, a homography needs 4 or more");
  for (std::size_t i = 0; i < px.size(); ++i)
    if (!(std::isfinite(px[i].x) && std::isfinite(px[i].y) && std::isfinite(mm[i].x) && std::isfinite(mm[i].y)))
      throw Error("laser plane map: point pair " + std::to_string(i) + " is not finite");
  // The pixels must span the plane: the smaller principal spread of the
  // points (the root of the smaller eigenvalue of their covariance)
  // against the larger, as a line of points would have it zero.
  cv::Point2d mean(0, 0);
  for (const auto& p : px) mean += p * (1.0 / static_cast<double>(px.size()));
  double sxx = 0, syy = 0, sxy = 0;
  for (const auto& p : px) {
    const cv::Point2d d = p - mean;
    sxx += d.x * d.x, syy += d.y * d.y, sxy += d.x * d.y;
  }
  const double half_trace = 0.5 * (sxx + syy), root = std::hypot(0.5 * (sxx - syy), sxy);
  if (!(half_trace - root > 1e-6 * (half_trace + root)))
    throw Error("laser plane map: the pixel points lie on one line (or coincide); they must span the laser plane");
  const cv::Mat h = cv::findHomography(px, mm, 0);  // least squares over all pairs
  if (h.empty()) throw Error("laser plane map: the points are degenerate (collinear or repeated)");
  LaserPlaneMap map;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) map.mm_from_px(r, c) = h.at<double>(r, c);
  for (std::size_t i = 0; i < px.size(); ++i) {
    const cv::Point2d back = ToLaserPlane(map, px[i]);
    const double residual = std::hypot(back.x - mm[i].x, back.y - mm[i].y);
    if (!(residual <= max_residual_mm))
      throw Error("laser plane map: point pair " + std::to_string(i) + " is " + std::to_string(residual) +
                  " mm off the fitted map (limit " + std::to_string(max_residual_mm) +
                  " mm): a wrong correspondence, or a distorted frame");
  }
  return map;
}

cv::Point2d ToLaserPlane(const LaserPlaneMap& map, cv::Point2d px) {
  const cv::Matx33d& h = map.mm_from_px;
  const double w = h(2, 0) * px.x + h(2, 1) * px.y + h(2, 2);
  return {(h(0, 0) * px.x + h(0, 1) * px.y + h(0, 2)) / w, (h(1, 0) * px.x + h(1, 1) * px.y + h(1, 2)) / w};
}

}  // namespace bead::vision
