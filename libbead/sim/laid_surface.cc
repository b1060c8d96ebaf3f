#include "libbead/sim/laid_surface.h"

#include <algorithm>
#include <cmath>

namespace bead::sim {
namespace {

// The ellipse's material over `below` with its centre at height zc: the
// part of it above the old surface.
double MaterialArea(const Surface& below, double c, double a, double b, double zc, bool fill_under) {
  double area = 0.0;
  const std::size_t k0 = static_cast<std::size_t>(std::max(0.0, (c - a - below.x0) / kGridMm));
  for (std::size_t k = k0; k < below.z.size(); ++k) {
    const double x = below.x0 + (static_cast<double>(k) + 0.5) * kGridMm;
    const double u = (x - c) / a;
    if (u > 1.0) break;
    if (u < -1.0) continue;
    const double h = b * std::sqrt(1.0 - u * u);
    const double bottom = fill_under ? below.At(x) : std::max(zc - h, below.At(x));
    area += std::max(0.0, zc + h - bottom) * kGridMm;
  }
  return area;
}

}  // namespace

// Lays a layer's ellipse on `below` (sunk until its material is the
// layer's area) and returns the top envelope the sensor sees.
Surface Lay(const Surface& below, const Layer& layer, double a, double b, double* zc_out, bool fill_under) {
  double lo = *std::min_element(below.z.begin(), below.z.end()) - b;
  double hi = *std::max_element(below.z.begin(), below.z.end()) + b + layer.area / a;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (MaterialArea(below, layer.center, a, b, mid, fill_under) < layer.area ? lo : hi) = mid;
  }
  const double zc = 0.5 * (lo + hi);
  if (zc_out) *zc_out = zc;
  Surface top = below;
  for (std::size_t k = 0; k < top.z.size(); ++k) {
    const double u = (below.x0 + static_cast<double>(k) * kGridMm - layer.center) / a;
    if (std::abs(u) <= 1.0) top.z[k] = std::max(top.z[k], zc + b * std::sqrt(1.0 - u * u));
  }
  return top;
}

}  // namespace bead::sim
