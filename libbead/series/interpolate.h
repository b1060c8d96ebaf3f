// Sampled series helpers.
// Linear interpolation of y(t) at x over the first n samples, clamped to
// the end values outside [t[0], t[n-1]]; NaN for a NaN x or no samples.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "libbead/core/median.h"

namespace bead {

inline double InterpolateLinear(const double* t, const double* y, std::size_t n, double x) {
  if (std::isnan(x) || n == 0) return std::numeric_limits<double>::quiet_NaN();
  if (x <= t[0]) return y[0];
  if (x >= t[n - 1]) return y[n - 1];
  const std::size_t j = static_cast<std::size_t>(std::upper_bound(t, t + n, x) - t);
  return y[j - 1] + (x - t[j - 1]) / (t[j] - t[j - 1]) * (y[j] - y[j - 1]);
}

inline double InterpolateLinear(const std::vector<double>& t, const std::vector<double>& y, double x) {
  return InterpolateLinear(t.data(), y.data(), std::min(t.size(), y.size()), x);
}

// Median spacing of sample times (the nominal sampling step); 0 for fewer than 2.
inline double MedianStep(const std::vector<double>& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> d;
  d.reserve(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) d.push_back(t[i] - t[i - 1]);
  return MedianInPlace(d.data(), d.size());
}

}  // namespace bead
