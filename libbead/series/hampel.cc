#include "libbead/series/hampel.h"

#include "libbead/core/median.h"

#include <algorithm>
#include <cmath>

namespace bead {

double HampelAt(const double* x, std::size_t n, std::size_t i, int k, double nsigma, bool* outlier,
                std::vector<double>& window, double min_sigma) {
  // MATLAB's scale: the MAD of a normal distribution times this is its sigma.
  constexpr double kMadScale = 1.4826022185;
  *outlier = false;
  if (std::isnan(x[i])) return x[i];
  const std::size_t lo = i >= static_cast<std::size_t>(k) ? i - static_cast<std::size_t>(k) : 0;
  const std::size_t hi = std::min(n - 1, i + static_cast<std::size_t>(k));
  window.clear();
  for (std::size_t j = lo; j <= hi; ++j)
    if (!std::isnan(x[j])) window.push_back(x[j]);
  const double m = MedianInPlace(window.data(), window.size());
  for (double& v : window) v = std::abs(v - m);
  const double sigma = std::max(kMadScale * MedianInPlace(window.data(), window.size()), min_sigma);
  if (std::abs(x[i] - m) > nsigma * sigma) {
    *outlier = true;
    return m;
  }
  return x[i];
}

HampelResult Hampel(const std::vector<double>& x, int k, double nsigma, double min_sigma) {
  HampelResult r;
  const std::size_t n = x.size();
  r.y = x;
  r.outlier.assign(n, 0);
  std::vector<double> scratch;
  for (std::size_t i = 0; i < n; ++i) {
    bool out = false;
    r.y[i] = HampelAt(x.data(), n, i, k, nsigma, &out, scratch, min_sigma);
    r.outlier[i] = out;
    r.outliers += out;
  }
  return r;
}

}  // namespace bead
