// Image pixels to the laser plane. A pinhole camera images a plane by a
// homography (Hartley and Zisserman, Multiple View Geometry, 2nd ed.,
// sec. 2.3), so a point (u, v) of an undistorted frame lies on the laser
// plane at (x, z) = (h1 . p, h2 . p) / (h3 . p), p = (u, v, 1): the
// profile's own coordinates, mm. Lens distortion is removed before
// (cv::undistort with the camera's calibration); the map is fitted from
// points of known position on the plane (a calibration target in the
// laser's light).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace bead::vision {

struct LaserPlaneMap {
  cv::Matx33d mm_from_px = cv::Matx33d::eye();
};

// Least squares over four or more point pairs (not all on one line);
// throws bead::Error when they are too few or degenerate, or when a pair
// lies more than max_residual_mm off the fitted map.
LaserPlaneMap FitLaserPlaneMap(const std::vector<cv::Point2d>& px, const std::vector<cv::Point2d>& mm,
                               double max_residual_mm = 0.05);

// A pixel's position on the laser plane, mm (NaN in, NaN out).
cv::Point2d ToLaserPlane(const LaserPlaneMap& map, cv::Point2d px);

}  // namespace bead::vision
