// Frames of a laser stripe for the vision tests: each column a Gaussian
// across the rows, background + peak exp(-(v - c(u))^2 / (2 sigma^2)),
// rounded and clipped to the frame type (OpenCV's saturate_cast).
#pragma once

#include <opencv2/core.hpp>

#include <cmath>
#include <functional>

namespace bead::test {

struct Stripe {
  std::function<double(int)> centre_row;  // c(u), px
  double sigma_px, peak, background;
};

inline cv::Mat RenderStripe(int rows, int cols, const Stripe& s, int depth) {
  cv::Mat grey(rows, cols, CV_64F);
  for (int u = 0; u < cols; ++u) {
    const double c = s.centre_row(u);
    for (int v = 0; v < rows; ++v)
      grey.at<double>(v, u) = s.background + s.peak * std::exp(-(v - c) * (v - c) / (2 * s.sigma_px * s.sigma_px));
  }
  cv::Mat frame;
  grey.convertTo(frame, depth);
  return frame;
}

// A camera looking down at the laser plane, slightly tilted: x = -25 mm at
// column 0 to +25 mm at column 1250 (0.04 mm/px), z = 6 mm at row 0 down
// to z = -0.9 mm near row 460 (0.015 mm/px), with a perspective term:
// (x, z) = mm_from_px (u, v, 1) up to scale.
inline const cv::Matx33d kTiltedCamera(0.04, 0.0004, -25.0,  //
                                       0.0002, -0.015, 6.0,  //
                                       0.0, 4e-6, 1.0);

inline cv::Point2d Apply(const cv::Matx33d& h, cv::Point2d p) {
  const double w = h(2, 0) * p.x + h(2, 1) * p.y + h(2, 2);
  return {(h(0, 0) * p.x + h(0, 1) * p.y + h(0, 2)) / w, (h(1, 0) * p.x + h(1, 1) * p.y + h(1, 2)) / w};
}

// The row where column u of kTiltedCamera meets the outline z = f(x) on the
// laser plane: g(v) = z(u, v) - f(x(u, v)) falls with v (z falls 0.015 mm
// a row while x moves 0.0004 mm, against f's slope of at most 1), so
// bisection finds it.
inline double StripeRow(int u, const std::function<double(double)>& f) {
  double lo = 0.0, hi = 470.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const cv::Point2d p = Apply(kTiltedCamera, {static_cast<double>(u), mid});
    (p.y - f(p.x) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// A parabola 12 mm wide and 3 mm high on the surface z = 0: area
// 2/3 * 12 * 3 = 24 mm^2.
inline double Parabola12x3(double x) { return std::abs(x) < 6.0 ? 3.0 * (1.0 - x * x / 36.0) : 0.0; }

}  // namespace bead::test
