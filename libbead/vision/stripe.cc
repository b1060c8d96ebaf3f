#include "libbead/vision/stripe.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "libbead/core/error.h"

namespace bead::vision {
namespace {

// The offset of a peak from its middle sample, from the samples before
// (a), at (c) and after (d) it, all above the background.
double PeakOffset(double a, double c, double d) {
  if (a > 0.0 && d > 0.0) {
    const double la = std::log(a), lc = std::log(c), ld = std::log(d);
    const double curvature = la - 2.0 * lc + ld;
    if (curvature < 0.0) return 0.5 * (la - ld) / curvature;
  }
  const double curvature = a - 2.0 * c + d;
  return curvature < 0.0 ? 0.5 * (a - d) / curvature : 0.0;
}

}  // namespace

void StripeCentres(const cv::Mat& frame, const StripeOptions& options, std::vector<float>& rows_px) {
  if (frame.empty()) throw Error("camera frame: empty");
  double saturated = 0.0;
  switch (frame.type()) {
    case CV_8UC1: saturated = 255.0; break;
    case CV_16UC1: saturated = 65535.0; break;
    case CV_32FC1: saturated = std::numeric_limits<double>::infinity(); break;
    default:
      throw Error("camera frame: type " + cv::typeToString(frame.type()) +
                  ", expected one channel of 8-bit, 16-bit or 32-bit float grey levels");
  }
  cv::Mat grey;
  frame.convertTo(grey, CV_32F);
  const int rows = grey.rows, cols = grey.cols;
  // Row by row (the frame's memory order): each column's brightest row and
  // its darkest value.
  std::vector<float> peak(static_cast<std::size_t>(cols), -std::numeric_limits<float>::infinity());
  std::vector<float> floor(static_cast<std::size_t>(cols), std::numeric_limits<float>::infinity());
  std::vector<int> at(static_cast<std::size_t>(cols), 0);
  for (int v = 0; v < rows; ++v) {
    const float* row = grey.ptr<float>(v);
    for (int u = 0; u < cols; ++u) {
      const auto k = static_cast<std::size_t>(u);
      if (row[u] > peak[k]) peak[k] = row[u], at[k] = v;
      floor[k] = std::min(floor[k], row[u]);
    }
  }
  rows_px.assign(static_cast<std::size_t>(cols), std::numeric_limits<float>::quiet_NaN());
  for (int u = 0; u < cols; ++u) {
    const auto k = static_cast<std::size_t>(u);
    const int v = at[k];
    if (!(peak[k] - floor[k] >= options.min_peak) || v == 0 || v == rows - 1) continue;
    auto value = [&](int r) { return static_cast<double>(grey.at<float>(r, u)); };
    if (value(v) >= saturated) {
      int last = v;
      while (last + 1 < rows && value(last + 1) >= saturated) ++last;
      if (last == rows - 1) continue;  // runs off the frame
      rows_px[k] = static_cast<float>(0.5 * (v + last));
      continue;
    }
    const double b = floor[k];
    rows_px[k] = static_cast<float>(v + PeakOffset(value(v - 1) - b, value(v) - b, value(v + 1) - b));
  }
}

}  // namespace bead::vision
