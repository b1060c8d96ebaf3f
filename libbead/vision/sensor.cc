#include "libbead/vision/sensor.h"

#include <opencv2/calib3d.hpp>

#include <cmath>

namespace bead::vision {

void Undistort(const CameraModel& camera, std::vector<cv::Point2d>& px) {
  if (!camera.Known()) return;
  std::vector<cv::Point2d> in, out;
  std::vector<std::size_t> at;
  for (std::size_t k = 0; k < px.size(); ++k)
    if (std::isfinite(px[k].x) && std::isfinite(px[k].y)) in.push_back(px[k]), at.push_back(k);
  if (in.empty()) return;
  // The default stops after 5 fixed-point iterations (OpenCV's note):
  // too few at the frame's corners for a strong lens; iterate to 1e-9.
  cv::undistortPoints(in, out, camera.matrix, camera.distortion, cv::noArray(), camera.matrix,
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-9));
  for (std::size_t i = 0; i < at.size(); ++i) px[at[i]] = out[i];
}

}  // namespace bead::vision
