#include "libbead/sim/laid_surface.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bead::sim {
namespace {

// The bead's half height over b at u: sqrt(1 - u^2) for the ellipse, (1 -
// |u|^p)^(1/p) for the superellipse of exponent p.
double Half(double u, double p) {
  return p == 2.0 ? std::sqrt(1.0 - u * u) : std::pow(std::max(0.0, 1.0 - std::pow(std::abs(u), p)), 1.0 / p);
}

// The bead's columns over the truth grid (midpoints): the surface below and
// the bead's half height there, the same whatever height it settles at.
struct Column {
  double below, h;
};

std::vector<Column> Columns(const Surface& below, double c, double a, double b, double p) {
  std::vector<Column> columns;
  const std::size_t k0 = static_cast<std::size_t>(std::max(0.0, (c - a - below.x0) / below.dx));
  for (std::size_t k = k0; k < below.z.size(); ++k) {
    const double x = below.x0 + (static_cast<double>(k) + 0.5) * below.dx;
    const double u = (x - c) / a;
    if (u > 1.0) break;
    if (u >= -1.0) columns.push_back({below.At(x), b * Half(u, p)});
  }
  return columns;
}

// The bead's material with its centre at height zc: the part of it above
// the old surface.
double MaterialArea(const std::vector<Column>& columns, double dx, double zc, bool fill_under) {
  double area = 0.0;
  for (const Column& col : columns) {
    const double bottom = fill_under ? col.below : std::max(zc - col.h, col.below);
    area += std::max(0.0, zc + col.h - bottom) * dx;
  }
  return area;
}

}  // namespace

// Lays a layer's bead on `below` (sunk until its material is the layer's
// area) and returns the top envelope the sensor sees.
Surface Lay(const Surface& below, const Layer& layer, double a, double b, double* zc_out, bool fill_under,
            double exponent) {
  double lo = *std::min_element(below.z.begin(), below.z.end()) - b;
  double hi = *std::max_element(below.z.begin(), below.z.end()) + b + layer.area / a;
  const std::vector<Column> columns = Columns(below, layer.center, a, b, exponent);
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (MaterialArea(columns, below.dx, mid, fill_under) < layer.area ? lo : hi) = mid;
  }
  const double zc = 0.5 * (lo + hi);
  if (zc_out) *zc_out = zc;
  Surface top = below;
  for (std::size_t k = 0; k < top.z.size(); ++k) {
    const double u = (below.x0 + static_cast<double>(k) * below.dx - layer.center) / a;
    if (std::abs(u) <= 1.0) top.z[k] = std::max(top.z[k], zc + b * Half(u, exponent));
  }
  return top;
}

}  // namespace bead::sim
