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

// std::upper_bound(t, t + n, x) - t, searched from `hint` (a previous
// answer) outward in doubling steps: O(log distance) instead of O(log n),
// for queries that move little from one to the next.
inline std::size_t UpperBoundNear(const double* t, std::size_t n, double x, std::size_t hint) {
  hint = std::min(hint, n);
  if (hint < n && t[hint] <= x) {  // the answer lies in (hint, n]; t[k] <= x for every k < lo
    std::size_t lo = hint + 1, hi = lo, step = 1;
    while (hi < n && t[hi] <= x) {
      lo = hi + 1;
      hi = lo + step;
      step <<= 1;
    }
    hi = std::min(hi, n);
    return static_cast<std::size_t>(std::upper_bound(t + lo, t + hi, x) - t);
  }
  // The answer lies in [0, hint]; t[k] > x for every k >= hi.
  std::size_t hi = hint, step = 1;
  while (hi > 0) {
    const std::size_t probe = hi > step ? hi - step : 0;
    if (t[probe] <= x) return static_cast<std::size_t>(std::upper_bound(t + probe + 1, t + hi, x) - t);
    hi = probe;
    step <<= 1;
  }
  return 0;
}

// InterpolateLinear, its search started from `hint` (updated): the same
// value bit for bit, for query times that run (nearly) in order.
inline double InterpolateLinearNear(const std::vector<double>& tv, const std::vector<double>& yv, double x,
                                    std::size_t& hint) {
  const std::size_t n = std::min(tv.size(), yv.size());
  const double *t = tv.data(), *y = yv.data();
  if (std::isnan(x) || n == 0) return std::numeric_limits<double>::quiet_NaN();
  if (x <= t[0]) return y[0];
  if (x >= t[n - 1]) return y[n - 1];
  const std::size_t j = hint = UpperBoundNear(t, n, x, hint);
  return y[j - 1] + (x - t[j - 1]) / (t[j] - t[j - 1]) * (y[j] - y[j - 1]);
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
