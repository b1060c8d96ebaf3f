// Hampel outlier filter with MATLAB `hampel` semantics: for each sample i
// the window x(max(1, i-k) : min(n, i+k)) (truncated at the ends), its
// median m and MAD scaled by 1.4826022185 (sigma); x(i) is an outlier when
// |x(i) - m| > nsigma * sigma (strictly) and is replaced by m.
// Extensions: NaN samples are left out of every window and stay NaN; an
// optional floor on sigma (default 0: MATLAB's behaviour) keeps a window
// whose samples happen to agree closely from calling ordinary noise an outlier.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bead {

struct HampelResult {
  std::vector<double> y;         // filtered
  std::vector<uint8_t> outlier;  // 1 where a sample was replaced
  int outliers = 0;
};

HampelResult Hampel(const std::vector<double>& x, int half_window, double nsigma, double min_sigma = 0.0);

// One sample: the Hampel decision for x[i] of x[0..n), returning the value
// to use (x[i] or the window median) and whether it was an outlier. The
// batch filter and the streaming flow both call this.
double HampelAt(const double* x, std::size_t n, std::size_t i, int half_window, double nsigma, bool* outlier,
                std::vector<double>& scratch, double min_sigma = 0.0);

}  // namespace bead
