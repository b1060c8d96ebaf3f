// Linear interpolation of y(t) at x over the first n samples, clamped to
// the end values outside [t[0], t[n-1]]; NaN for a NaN x or no samples.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace bead {

inline double InterpolateLinear(const double* t, const double* y, std::size_t n, double x) {
  if (std::isnan(x) || n == 0) return std::numeric_limits<double>::quiet_NaN();
  if (x <= t[0]) return y[0];
  if (x >= t[n - 1]) return y[n - 1];
  const std::size_t j = static_cast<std::size_t>(std::upper_bound(t, t + n, x) - t);
  return y[j - 1] + (x - t[j - 1]) / (t[j] - t[j - 1]) * (y[j] - y[j - 1]);
}

}  // namespace bead
