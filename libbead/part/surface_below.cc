#include "libbead/part/surface_below.h"

#include <algorithm>
#include <cmath>

namespace bead::part {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// z of a stored profile at x: linear between its valid points, NaN beyond
// its ends or across a gap longer than max_gap; `variance` its noise
// variance over one point's, (1 - t)^2 + t^2. `at`: where the last call
// with a smaller x found its point (the grid's x rise: a walk from there
// finds what std::lower_bound would).
double ProfileAt(const StoredProfile& p, double x, double max_gap, double& variance, std::size_t& at) {
  const auto xf = static_cast<float>(x);
  while (at < p.x_mm.size() && p.x_mm[at] < xf) ++at;
  if (at == p.x_mm.size()) return kNaN;
  const std::size_t k = at;
  variance = 1.0;
  if (p.x_mm[k] == x) return p.z_mm[k];
  if (k == 0) return kNaN;
  const double x0 = p.x_mm[k - 1], x1 = p.x_mm[k];
  if (x1 - x0 > max_gap) return kNaN;
  const double t = (x - x0) / (x1 - x0);
  variance = (1 - t) * (1 - t) + t * t;
  return p.z_mm[k - 1] + t * (p.z_mm[k] - p.z_mm[k - 1]);
}

}  // namespace

double SurfaceGrid::SlopeAt(double x) const {
  if (z_mm.size() < 2 || !(dx_mm > 0)) return kNaN;
  const double u = (x - x0_mm) / dx_mm;
  if (!(u >= 0.0) || u > static_cast<double>(z_mm.size() - 1)) return kNaN;
  const std::size_t k = std::min(static_cast<std::size_t>(u), z_mm.size() - 2);
  return (z_mm[k + 1] - z_mm[k]) / dx_mm;
}

void SurfaceBelow::BeginLayer(int64_t layer) {
  if (layer == layer_) return;
  below_known_ = layer == layer_ + 1 && !current_.empty();
  below_ = below_known_ ? std::move(current_) : std::vector<StoredProfile>{};
  current_.clear();
  std::sort(below_.begin(), below_.end(),
            [](const StoredProfile& a, const StoredProfile& b) { return a.path_mm < b.path_mm; });
  layer_ = layer;
}

bool SurfaceBelow::Neighbours(double path, std::size_t& i, std::size_t& j, double& w, std::string* why) const {
  if (!below_known_) {
    if (why) *why = "layer " + std::to_string(layer_ - 1) + " is not in the scan";
    return false;
  }
  const auto it = std::lower_bound(below_.begin(), below_.end(), path,
                                   [](const StoredProfile& p, double v) { return p.path_mm < v; });
  j = static_cast<std::size_t>(it - below_.begin());
  if (j == below_.size()) j = below_.size() - 1;
  i = j > 0 && below_[j].path_mm > path ? j - 1 : j;
  const double gap = std::max(std::abs(path - below_[i].path_mm), std::abs(below_[j].path_mm - path));
  if (gap > options_.max_path_gap_mm) {
    if (why)
      *why = "layer " + std::to_string(layer_ - 1) + " was not scanned within " +
             std::to_string(options_.max_path_gap_mm) + " mm of path " + std::to_string(path) + " mm";
    return false;
  }
  const double span = below_[j].path_mm - below_[i].path_mm;
  w = span > 0 ? std::clamp((path - below_[i].path_mm) / span, 0.0, 1.0) : 0.0;
  return true;
}

std::optional<SurfaceGrid> SurfaceBelow::At(double path, double dx, std::string* why) const {
  std::size_t i = 0, j = 0;
  double w = 0;
  if (!Neighbours(path, i, j, w, why)) return std::nullopt;
  const StoredProfile &a = below_[i], &b = below_[j];
  if (a.x_mm.size() < 2 || b.x_mm.size() < 2) {
    if (why) *why = "the layer below holds too few points here";
    return std::nullopt;
  }
  SurfaceGrid g;
  g.dx_mm = dx;
  g.x0_mm = std::min(a.x_mm.front(), b.x_mm.front());
  const double x1 = std::max(a.x_mm.back(), b.x_mm.back());
  const std::size_t n = GridPoints(g.x0_mm, x1, dx);
  if (n < 2) {
    if (why) *why = "the layer below spans too wide an x range for its point spacing";
    return std::nullopt;
  }
  g.z_mm.resize(n);
  g.variance.resize(n);
  const double gap = options_.max_x_gap_mm;
  std::size_t at_a = 0, at_b = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double x = g.x0_mm + static_cast<double>(k) * dx;
    double va = 1.0, vb = 1.0;
    const double za = ProfileAt(a, x, gap, va, at_a), zb = ProfileAt(b, x, gap, vb, at_b);
    // Where only one of the two saw the surface, it stands for both.
    const double z = std::isnan(za) ? zb : std::isnan(zb) ? za : (1 - w) * za + w * zb;
    const double v = std::isnan(za) ? vb : std::isnan(zb) ? va : (1 - w) * (1 - w) * va + w * w * vb;
    g.z_mm[k] = static_cast<float>(z);
    g.variance[k] = static_cast<float>(v);
  }
  return g;
}

double SurfaceBelow::CenterAt(double path) const {
  std::size_t i = 0, j = 0;
  double w = 0;
  if (!Neighbours(path, i, j, w, nullptr)) return kNaN;
  return (1 - w) * below_[i].center_x_mm + w * below_[j].center_x_mm;
}

}  // namespace bead::part
