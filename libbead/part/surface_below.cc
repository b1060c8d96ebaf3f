#include "libbead/part/surface_below.h"

#include <algorithm>
#include <cmath>

namespace bead::part {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A stored profile on the grid x0 + k dx, k < n: linear between its valid
// points, NaN beyond its ends or across a gap longer than max_gap; its
// variance over one point's, (1 - t)^2 + t^2 (1 on a point). Filled
// segment by segment: each segment's grid points, from the first at or
// after its left point to the last before its right one.
void Resample(const StoredProfile& p, double x0, double dx, std::size_t n, double max_gap, std::vector<float>& z,
              std::vector<float>& variance) {
  z.assign(n, static_cast<float>(kNaN));
  variance.assign(n, 1.0f);
  const std::size_t points = p.x_mm.size();
  if (points == 0) return;
  // The first grid point at or after x (a hair's tolerance: a grid point on x belongs to it).
  auto first_at = [&](double x) {
    const double u = std::ceil((x - x0) / dx - 1e-9);
    return u <= 0.0 ? std::size_t{0} : std::min(n, static_cast<std::size_t>(u));
  };
  std::size_t k = first_at(p.x_mm[0]);
  for (std::size_t i = 0; i + 1 < points && k < n; ++i) {
    const double xa = p.x_mm[i], xb = p.x_mm[i + 1];
    const std::size_t end = std::max(k, first_at(xb));
    if (xb - xa <= max_gap && xb > xa) {
      const double za = p.z_mm[i], rise = static_cast<double>(p.z_mm[i + 1]) - za, inv = 1.0 / (xb - xa);
      for (std::size_t j = k; j < end; ++j) {
        const double t = (x0 + static_cast<double>(j) * dx - xa) * inv;
        z[j] = static_cast<float>(za + t * rise);
        variance[j] = static_cast<float>((1 - t) * (1 - t) + t * t);
      }
    }
    k = end;
  }
  // The last point's own grid point.
  if (k < n && std::abs(x0 + static_cast<double>(k) * dx - p.x_mm.back()) <= 1e-9 * std::max(1.0, std::abs(dx)))
    z[k] = p.z_mm.back();
}

}  // namespace

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
  const double gap = options_.max_x_gap_mm;
  Resample(a, g.x0_mm, dx, n, gap, g.z_mm, g.variance);
  Resample(b, g.x0_mm, dx, n, gap, za_, va_);  // the second profile's
  // Where only one of the two saw the surface, it stands for both.
  for (std::size_t k = 0; k < n; ++k) {
    const float z1 = g.z_mm[k], z2 = za_[k];
    if (std::isnan(z2)) continue;
    if (std::isnan(z1)) {
      g.z_mm[k] = z2, g.variance[k] = va_[k];
      continue;
    }
    g.z_mm[k] = static_cast<float>((1 - w) * z1 + w * z2);
    g.variance[k] = static_cast<float>((1 - w) * (1 - w) * g.variance[k] + w * w * va_[k]);
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
