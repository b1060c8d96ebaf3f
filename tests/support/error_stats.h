// The figures tests read errors by: their RMS, their median and that of their sizes,
// and whether two values are the same bits (or both NaN). Shared, so that a
// suite's files compile as one (tests/CMakeLists.txt: a unity build) without
// each holding its own.
#pragma once

#include <cmath>
#include <cstring>
#include <vector>

#include "libbead/core/median.h"

namespace bead::test {

// NaN where there is none.
inline double Rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? NAN : std::sqrt(s / static_cast<double>(v.size()));
}

// The median of v (the two middle ones' mean for an even count); NaN where
// there is none.
inline double Median(std::vector<double> v) { return v.empty() ? NAN : MedianInPlace(v.data(), v.size()); }

// The median of |v| (the two middle ones' mean for an even count); NaN where
// there is none.
inline double MedianAbs(std::vector<double> v) {
  for (double& x : v) x = std::abs(x);
  return v.empty() ? NAN : MedianInPlace(v.data(), v.size());
}

inline bool SameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

}  // namespace bead::test
