#include "libbead/occlusion/occlusion_pool.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "libbead/core/median.h"

namespace bead::occlusion {

std::vector<std::size_t> PoolRanks(std::size_t valid_count, int max_fits) {
  // Evenly spread over the valid profiles.
  const std::size_t fits = std::min<std::size_t>(valid_count, static_cast<std::size_t>(std::max(max_fits, 1)));
  std::vector<std::size_t> ranks(fits);
  for (std::size_t j = 0; j < fits; ++j) ranks[j] = (j * valid_count + valid_count / 2) / fits;
  return ranks;
}

PooledOcclusion PoolFromFits(const std::vector<OcclusionEstimate>& fits, const std::vector<BeadGeometry>& geometry) {
  PooledOcclusion pool;
  if (fits.empty()) {
    pool.note = "no measured profile to fit";
    return pool;
  }
  std::vector<double> fraction, rel_sigma;
  std::map<std::string, int> families;
  int constrained = 0;
  for (std::size_t j = 0; j < fits.size(); ++j) {
    const BeadGeometry& g = geometry[j];
    const OcclusionEstimate& e = fits[j];
    if (!e.ok || !(g.area_mm2 > 0)) continue;
    fraction.push_back(e.bias_mm2 / g.area_mm2);
    // The estimate's sigma less the area's own, which ApplyPooled adds per profile.
    const double own = g.area_sigma_mm2;
    rel_sigma.push_back(std::sqrt(std::max(0.0, e.sigma_mm2 * e.sigma_mm2 - own * own)) / g.area_mm2);
    ++families[e.family];
    constrained += e.constrained;
  }
  pool.fitted = static_cast<int>(fraction.size());
  if (fraction.empty()) {
    pool.note = "no profile's shape could be fitted";
    return pool;
  }
  std::vector<double> work = fraction;
  pool.bias_fraction = MedianInPlace(work.data(), work.size());
  for (std::size_t k = 0; k < work.size(); ++k) work[k] = std::abs(fraction[k] - pool.bias_fraction);
  const double spread = 1.4826 * MedianInPlace(work.data(), work.size());
  work = rel_sigma;
  const double typical = MedianInPlace(work.data(), work.size());
  pool.fraction_sigma = std::hypot(typical, spread);
  pool.constrained = 2 * constrained > pool.fitted;
  pool.family = std::max_element(families.begin(), families.end(), [](const auto& a, const auto& b) {
                  return a.second < b.second;
                })->first;
  pool.ok = true;
  if (!pool.constrained)
    pool.note = "the hidden part is not constrained by the data (see the rounded rectangle's bottom radius)";
  return pool;
}

CorrectedArea ApplyPooled(const PooledOcclusion& pooled, const BeadGeometry& g) {
  const double nan = std::nan("");
  if (!pooled.ok || !g.valid()) return {nan, nan, nan};
  const double bias = pooled.bias_fraction * g.area_mm2;
  const double sigma = std::hypot(pooled.fraction_sigma * g.area_mm2, g.area_sigma_mm2);
  return {g.area_mm2 - bias, bias, sigma};
}

}  // namespace bead::occlusion
