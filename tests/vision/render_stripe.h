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

}  // namespace bead::test
