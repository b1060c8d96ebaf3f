#include "libbead/series/hampel.h"

#include <algorithm>
#include <cmath>

namespace bead {
namespace {

double Median(std::vector<double>& v) {
  const std::size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<long>(n / 2), v.end());
  const double hi = v[n / 2];
  if (n % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<long>(n / 2)));
}

}  // namespace

HampelResult Hampel(const std::vector<double>& x, int k, double nsigma) {
  // MATLAB's scale: the MAD of a normal distribution times this is its sigma.
  constexpr double kMadScale = 1.4826022185;
  HampelResult r;
  const std::size_t n = x.size();
  r.y = x;
  r.outlier.assign(n, 0);
  std::vector<double> window, dev;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(x[i])) continue;
    const std::size_t lo = i >= static_cast<std::size_t>(k) ? i - static_cast<std::size_t>(k) : 0;
    const std::size_t hi = std::min(n - 1, i + static_cast<std::size_t>(k));
    window.clear();
    for (std::size_t j = lo; j <= hi; ++j)
      if (!std::isnan(x[j])) window.push_back(x[j]);
    const double m = Median(window);
    dev.clear();
    for (double v : window) dev.push_back(std::abs(v - m));
    const double sigma = kMadScale * Median(dev);
    if (std::abs(x[i] - m) > nsigma * sigma) {
      r.y[i] = m;
      r.outlier[i] = 1;
      ++r.outliers;
    }
  }
  return r;
}

}  // namespace bead
