// Medians of small buffers, in place (the buffer is reordered).
#pragma once

#include <algorithm>
#include <cstddef>

namespace bead {

template <typename T>
inline T MedianInPlace(T* values, std::size_t n) {
  T* mid = values + n / 2;
  std::nth_element(values, mid, values + n);
  if (n % 2 == 1) return *mid;
  return T(0.5) * (*mid + *std::max_element(values, mid));
}

// The middle value of a buffer, in place (reordered; n > 0): for an even
// count the upper of the two middle ones, a value the buffer holds (a rank,
// not an average: a robust scale, a shift or a ratio read from the data).
template <typename T>
inline T MiddleInPlace(T* values, std::size_t n) {
  T* mid = values + n / 2;
  std::nth_element(values, mid, values + n);
  return *mid;
}
template <typename Container>
inline auto MiddleInPlace(Container& c) {
  return MiddleInPlace(c.data(), c.size());
}

template <typename T>
inline T Median3(T a, T b, T c) {
  return std::max(std::min(a, b), std::min(std::max(a, b), c));
}

// Median of five: the median of e and the two middle candidates of the
// pairs (a, b) and (c, d).
template <typename T>
inline T Median5(T a, T b, T c, T d, T e) {
  const T lo = std::max(std::min(a, b), std::min(c, d));
  const T hi = std::min(std::max(a, b), std::max(c, d));
  return Median3(lo, hi, e);
}

}  // namespace bead
