// A plane through 3-D points with outliers (the laser stripe lifted onto
// the calibration board, where part of it may fall on another surface),
// and the map from undistorted pixels to coordinates on that plane.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace bead::calibration {

struct PlaneFit {
  cv::Vec4d plane;           // a x + b y + c z + d = 0, (a, b, c) unit, d >= 0 (the origin on the + side)
  double sigma_mm = 0.0;     // robust spread of the distances (1.4826 MAD)
  std::vector<bool> inlier;  // within 3 sigma of the plane (and of 0.01 mm)
  int inliers = 0;
  double rms_mm = 0.0;  // over the inliers
};

// Least squares (the smallest singular vector of the centred points)
// first, then Ceres with a Cauchy loss of scale sigma re-estimated twice
// (Ceres Solver's CauchyLoss: rho(s) = b log(1 + s / b), b = scale^2).
// Throws bead::Error with fewer than 10 points or points on one line.
PlaneFit FitPlaneRobust(const std::vector<cv::Point3d>& points);

double Distance(const cv::Vec4d& plane, const cv::Point3d& p);

// Coordinates on the plane: origin o (on the plane), unit axes e_x, e_z
// in it. The homography H with (x, z) = (H p)[0..1] / (H p)[2] for an
// undistorted pixel p = (u, v, 1) of a camera with matrix K: the ray
// r = K^-1 p meets the plane at P = -d r / (n . r), so
// x = e_x . (P - o) = (-d e_x . r - (e_x . o)(n . r)) / (n . r), and z the
// same with e_z (Hartley and Zisserman, 2nd ed., sec. 8.1.1: a plane's
// image is a homography).
cv::Matx33d PlaneHomography(const cv::Matx33d& camera, const cv::Vec4d& plane, const cv::Vec3d& origin,
                            const cv::Vec3d& e_x, const cv::Vec3d& e_z);

}  // namespace bead::calibration
