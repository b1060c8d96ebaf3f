// Medians of small buffers, in place (the buffer is reordered).
#pragma once

#include <algorithm>
#include <cstddef>

namespace bead {

inline double MedianInPlace(double* values, std::size_t n) {
  double* mid = values + n / 2;
  std::nth_element(values, mid, values + n);
  if (n % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(values, mid));
}

inline double Median3(double a, double b, double c) {
  return std::max(std::min(a, b), std::min(std::max(a, b), c));
}

}  // namespace bead

namespace bead {

// Median of five: the median of e and the two middle candidates of the
// pairs (a, b) and (c, d).
inline double Median5(double a, double b, double c, double d, double e) {
  const double lo = std::max(std::min(a, b), std::min(c, d));
  const double hi = std::min(std::max(a, b), std::max(c, d));
  return Median3(lo, hi, e);
}

}  // namespace bead
