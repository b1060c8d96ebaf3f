// A camera-and-laser sensor as calibrated (`bead calibrate laser`): the
// camera's intrinsics and lens distortion, the laser plane, the map from
// undistorted pixels to the plane, and how to find the stripe.
//
// Lens model: OpenCV's (Brown-Conrady) radial-tangential distortion with
// coefficients [k1, k2, p1, p2, k3] on normalised image coordinates; the
// camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] in pixels. Frames
// are not undistorted as images: each stripe point is (cv::undistortPoints
// with the camera matrix as the new projection), then mapped.
#pragma once

#include <opencv2/core.hpp>
#include <array>
#include <vector>

#include "libbead/vision/laser_plane.h"
#include "libbead/vision/stripe.h"

namespace bead::vision {

struct CameraModel {
  cv::Matx33d matrix = cv::Matx33d::eye();
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3
  cv::Size image_size;                 // width, height, px; empty: no lens model
  bool Known() const { return image_size.area() > 0; }
};

struct SensorModel {
  CameraModel camera;
  // a x + b y + c z + d = 0 in camera coordinates (mm, x right, y down,
  // z along the optical axis), (a, b, c) a unit vector; zero when the
  // sensor came from a plane file of point pairs.
  cv::Vec4d plane;
  LaserPlaneMap map;  // undistorted pixel -> (x_mm, z_mm) on the laser plane
  StripeOptions stripe;
};

// Undistorted pixel positions of distorted ones (the same when the camera
// is not known); NaN stays NaN.
void Undistort(const CameraModel& camera, std::vector<cv::Point2d>& px);

}  // namespace bead::vision
