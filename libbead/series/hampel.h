// Hampel outlier filter with MATLAB `hampel` semantics: for each sample i
// the window x(max(1, i-k) : min(n, i+k)) (truncated at the ends), its
// median m and MAD scaled by 1.4826022185 (sigma); x(i) is an outlier when
// |x(i) - m| > nsigma * sigma (strictly) and is replaced by m.
// Extension for gaps: NaN samples are left out of every window and stay NaN.
#pragma once

#include <cstdint>
#include <vector>

namespace bead {

struct HampelResult {
  std::vector<double> y;          // filtered
  std::vector<uint8_t> outlier;   // 1 where a sample was replaced
  int outliers = 0;
};

HampelResult Hampel(const std::vector<double>& x, int half_window, double nsigma);

}  // namespace bead
