#include "libbead/part/surface_below.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "libbead/core/float_bits.h"
#include "libbead/core/median.h"
#include "libbead/part/added_bead.h"
#include "libbead/part/part_kernel.h"

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

// Whether x[j] lies within a hundredth of dx of x[0] + j dx for every j
// (a sensor's points on its grid, none missing): one pass, no branch.
bool OnEveryGridPoint(std::span<const float> x, double dx) {
  const float x0 = x[0], step = static_cast<float>(dx), tolerance = static_cast<float>(0.01 * dx);
  // (An int index: a 64-bit one turns into a float one point at a time.)
  int off = 0;
  const auto n = static_cast<int>(x.size());
  for (int j = 0; j < n; ++j) off |= std::abs(x[j] - (x0 + static_cast<float>(j) * step)) > tolerance;
  return off == 0;
}

// Each run of missing values between two known ones bridged where the
// run's two ends lie no farther apart than max_gap: linearly (variance
// (1 - t)^2 + t^2), or across a wall (the surface rising or falling by
// more than the run is long: points a triangulation shadow lost beside a
// bead) as a step at the run's middle, each side's height held to it. (A
// ramp there, under the next layer's bead, made the old bead's top a gain:
// +9 % on a layer of an independent wall; the run left unknown, +1.3 to
// +4.4 % over the run.)
void Bridge(double max_gap, SurfaceRow& row) {
  const std::size_t n = row.z_mm.size();
  std::size_t ka = 0;
  while (ka < n && std::isnan(row.z_mm[ka])) ++ka;
  for (std::size_t kb = ka + 1; kb < n; ++kb) {
    if (std::isnan(row.z_mm[kb])) continue;
    const double length = static_cast<double>(kb - ka) * row.dx_mm;
    const bool wall = std::abs(row.z_mm[kb] - row.z_mm[ka]) > length;
    if (kb > ka + 1 && length <= max_gap)
      for (std::size_t k = ka + 1; k < kb; ++k) {
        const double t = static_cast<double>(k - ka) / static_cast<double>(kb - ka);
        if (wall) {
          row.z_mm[k] = t < 0.5 ? row.z_mm[ka] : row.z_mm[kb];
          continue;
        }
        row.z_mm[k] = static_cast<float>((1 - t) * row.z_mm[ka] + t * row.z_mm[kb]);
        row.variance[k] = static_cast<float>((1 - t) * (1 - t) + t * t);
      }
    ka = kb;
  }
}

// Two rows of points on one grid (the same spacing, the second's start a
// whole number of spacings from the first's: a sensor's uniform points in
// passes whose frames differ by as much) blended value by value as
// SurfaceGrid blends them, into r (its buffers reused): the same surface,
// sampled with one lookup. False where the two grids differ.
bool Blend(const SurfaceRow& a, const SurfaceRow& b, double w, SurfaceRow& r) {
  if (!a.at_points || !b.at_points || std::abs(a.dx_mm - b.dx_mm) > 1e-6 * a.dx_mm) return false;
  const double offset = (b.x0_mm - a.x0_mm) / a.dx_mm, whole = std::round(offset);
  if (std::abs(offset - whole) > 1e-3) return false;
  const auto shift = static_cast<std::ptrdiff_t>(whole);  // b's value k is a's k + shift
  const std::ptrdiff_t na = std::ssize(a.z_mm), nb = std::ssize(b.z_mm);
  const std::ptrdiff_t first = std::min<std::ptrdiff_t>(0, shift), end = std::max(na, shift + nb);  // in a's index
  r.dx_mm = a.dx_mm, r.x0_mm = a.x0_mm + static_cast<double>(first) * a.dx_mm, r.at_points = true;
  r.z_mm.assign(static_cast<std::size_t>(end - first), NAN);
  r.variance.assign(r.z_mm.size(), 1.0f);
  // Index k of a is r's k - first, b's k - shift. Each row where it alone
  // reaches, then the two blended where both do (one NaN: the other
  // stands for both).
  const auto at = [](auto& v, std::ptrdiff_t i) -> auto& { return v[static_cast<std::size_t>(i)]; };
  std::copy(a.z_mm.begin(), a.z_mm.end(), r.z_mm.begin() - first);
  std::copy(a.variance.begin(), a.variance.end(), r.variance.begin() - first);
  const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(0, shift), hi = std::min(na, shift + nb);
  const auto b_alone = [&](std::ptrdiff_t from, std::ptrdiff_t to) {
    for (std::ptrdiff_t k = from; k < to; ++k)
      at(r.z_mm, k - first) = at(b.z_mm, k - shift), at(r.variance, k - first) = at(b.variance, k - shift);
  };
  b_alone(shift, std::min(lo, shift + nb));
  b_alone(std::max(hi, shift), shift + nb);
  const float wa = static_cast<float>(1 - w), wb = static_cast<float>(w);
  float *rz = r.z_mm.data() + (lo - first), *rv = r.variance.data() + (lo - first);
  const float *bz = b.z_mm.data() + (lo - shift), *bv = b.variance.data() + (lo - shift);
  // On pointers, both ways computed and one kept, chosen by integer masks
  // from the values' bits (b's NaN keeps a's, a's alone b's;
  // core/float_bits.h): a loop the compiler makes four values a step.
  const auto bits = [](float v) { return std::bit_cast<uint32_t>(v); };
  for (std::ptrdiff_t k = 0; k < hi - lo; ++k) {
    const float za = rz[k], va = rv[k], zb = bz[k], vb = bv[k];
    const uint32_t b_nan = 0u - static_cast<uint32_t>(IsNanBits(zb));
    const uint32_t a_nan = (0u - static_cast<uint32_t>(IsNanBits(za))) & ~b_nan;
    const uint32_t both = ~(a_nan | b_nan);
    const float v = wa * wa * va + wb * wb * vb, z = wa * za + wb * zb;
    rv[k] = std::bit_cast<float>((bits(va) & b_nan) | (bits(vb) & a_nan) | (bits(v) & both));
    rz[k] = std::bit_cast<float>((bits(za) & b_nan) | (bits(zb) & a_nan) | (bits(z) & both));
  }
  return true;
}

}  // namespace

SurfaceRow RowOf(const StoredProfile& p, double max_gap) {
  SurfaceRow row;
  RowOf(p, max_gap, row);
  return row;
}

void RowOf(const StoredProfile& p, double max_gap, SurfaceRow& row) {
  row.x0_mm = row.dx_mm = 0.0, row.at_points = false;
  row.z_mm.clear(), row.variance.clear();
  if (p.x_mm.size() < 2) return;
  // The points' own grid: x0 the first, dx from the first to the last over
  // the last's index.
  const double span = static_cast<double>(p.x_mm.back()) - p.x_mm.front(), last = std::round(span / p.spacing_mm);
  if (last >= 1.0 && last + 1.0 < static_cast<double>(kMaxGridPoints) &&
      PlaceOnGrid(p.x_mm, p.z_mm, span / last, static_cast<std::size_t>(last) + 1, row.z_mm)) {
    row.x0_mm = p.x_mm.front(), row.dx_mm = span / last, row.at_points = true;
    row.variance.assign(row.z_mm.size(), 1.0f);
    if (row.z_mm.size() > p.z_mm.size()) Bridge(max_gap, row);
    return;
  }
  row.z_mm.clear();  // what a placement that failed left
  row.dx_mm = std::max(0.125 * p.spacing_mm, 1e-4);
  row.x0_mm = p.x_mm.front();
  const std::size_t n = GridPoints(p.x_mm.front(), p.x_mm.back(), row.dx_mm);
  if (n >= 2) Resample(p, row.x0_mm, row.dx_mm, n, max_gap, row.z_mm, row.variance);
}

bool PlaceOnGrid(std::span<const float> x, std::span<const float> z, double dx, std::size_t n,
                 std::vector<float>& out) {
  if (x.empty() || !(dx > 0.0)) return false;
  if (n == x.size() && OnEveryGridPoint(x, dx)) {
    out.assign(z.begin(), z.end());
    return true;
  }
  out.assign(n, static_cast<float>(kNaN));
  const double x0 = x[0], per_mm = 1.0 / dx;
  std::ptrdiff_t before = -1;
  for (std::size_t j = 0; j < x.size(); ++j) {
    // x increases from x0: u >= 0 but for rounding, and the nearest whole
    // number is the truncation of u + 1/2.
    const double u = (x[j] - x0) * per_mm;
    const auto k = static_cast<std::ptrdiff_t>(u + 0.5);
    if (std::abs(u - static_cast<double>(k)) > 0.01 || k <= before || k >= std::ssize(out)) return false;
    out[static_cast<std::size_t>(k)] = z[j];
    before = k;
  }
  return true;
}

void SurfaceBelow::BeginLayer(int64_t layer) {
  if (layer == layer_) return;
  below_known_ = layer == layer_ + 1 && !current_.empty();
  // The rows let go that no grid handed out still holds, to be refilled.
  std::vector<std::shared_ptr<SurfaceRow>> retired;
  for (Below& b : below_)
    if (b.row.use_count() == 1) retired.push_back(std::move(b.row));
  below_.clear();
  if (below_known_) {
    std::sort(current_.begin(), current_.end(),
              [](const StoredProfile& a, const StoredProfile& b) { return a.path_mm < b.path_mm; });
    for (const StoredProfile& p : current_) {
      std::shared_ptr<SurfaceRow> row;
      if (retired.empty())
        row = std::make_shared<SurfaceRow>();
      else
        row = std::move(retired.back()), retired.pop_back();
      RowOf(p, options_.max_x_gap_mm, *row);
      below_.push_back({p.path_mm, p.center_x_mm, p.area_mm2, false, std::move(row)});
    }
    Steps();
  }
  // The profiles' buffers, for the next layer's profiles.
  spare_.clear();
  for (StoredProfile& p : current_) spare_.push_back(std::move(p.x_mm)), spare_.push_back(std::move(p.z_mm));
  current_.clear();
  layer_ = layer;
}

std::vector<float> SurfaceBelow::Spare() {
  if (spare_.empty()) return {};
  std::vector<float> v = std::move(spare_.back());
  spare_.pop_back();
  return v;
}

bool SurfaceBelow::Neighbours(double path, std::size_t& i, std::size_t& j, double& w, std::string* why) const {
  if (!below_known_) {
    if (why) *why = "layer " + std::to_string(layer_ - 1) + " is not in the scan";
    return false;
  }
  return PathNeighbours(
      below_, [](const Below& b) { return b.path_mm; }, path, options_.max_path_gap_mm, layer_ - 1, i, j, w, why);
}

std::optional<SurfaceGrid> SurfaceBelow::At(double path, std::string* why) const {
  std::size_t i = 0, j = 0;
  double w = 0;
  if (!Neighbours(path, i, j, w, why)) return std::nullopt;
  const Below &a = below_[i], &b = below_[j];
  if (a.row->z_mm.size() < 2 || b.row->z_mm.size() < 2) {
    if (why) *why = "the layer below holds too few points here, or spans too wide an x range for its point spacing";
    return std::nullopt;
  }
  if (i == j) return SurfaceGrid(a.row, nullptr, 0.0);
  // The blend's row reused where no grid handed out still holds it.
  if (!blended_ || blended_.use_count() > 1) blended_ = std::make_shared<SurfaceRow>();
  if (Blend(*a.row, *b.row, w, *blended_)) return SurfaceGrid(blended_, nullptr, 0.0);
  return SurfaceGrid(a.row, b.row, w);
}

// A pair lies where the layer steps where its change, or its neighbour's,
// leaves the trend by over three sigmas: a change less the trend beside it
// (the mean of the changes into the first and out of the second, where
// there are such), those sigmas 1.4826 times the median of the layer's (a
// normal's, from what most pairs, making no step, show). A change the
// layer makes steadily along the path, or curving, is followed by the
// blend; a step is not, nor is a ramp over a few profiles (a corner's bulge
// beginning over a millimetre: its middle pair follows the trend of its
// ends, and its edges move, which no blend of surfaces does). (The
// profiles' own noise as the sigma left a twin wall's overhanging beads,
// whose areas move with where the walls' cells place their ends, full of
// steps.)
void SurfaceBelow::Steps() {
  const auto area = [&](std::size_t k) { return below_[k].area_mm2; };
  const std::size_t pairs = below_.empty() ? 0 : below_.size() - 1;
  std::vector<double> off(pairs, NAN), sizes;
  for (std::size_t k = 0; k < pairs; ++k) {
    const bool before = k > 0, after = k + 2 < below_.size();
    const double into = before ? area(k) - area(k - 1) : NAN, out = after ? area(k + 2) - area(k + 1) : NAN;
    const double trend = before && after ? 0.5 * (into + out) : before ? into : after ? out : 0.0;
    off[k] = std::abs(area(k + 1) - area(k) - trend);
    if (std::isfinite(off[k])) sizes.push_back(off[k]);
  }
  if (sizes.empty()) return;
  // (At least 1e-6 mm^2, far under any profile's area noise: a layer
  // whose areas lie on their trend to rounding had every pair a step.)
  const double beyond = std::max(3.0 * 1.4826 * MiddleInPlace(sizes), 1e-6);
  for (std::size_t k = 0; k < pairs; ++k)
    if (off[k] > beyond)
      for (std::size_t n = k > 0 ? k - 1 : 0; n <= std::min(k + 1, pairs - 1); ++n) below_[n].step = true;
}

BelowChange SurfaceBelow::ChangeAt(double path) const {
  std::size_t i = 0, j = 0;
  BelowChange c;
  if (!Neighbours(path, i, j, c.w, nullptr) || i == j) return c;
  c.change_mm2 = below_[j].area_mm2 - below_[i].area_mm2;
  c.step = below_[i].step;
  const double before = i > 0 ? c.change_mm2 - (below_[i].area_mm2 - below_[i - 1].area_mm2) : kNaN;
  const double after = j + 1 < below_.size() ? below_[j + 1].area_mm2 - below_[j].area_mm2 - c.change_mm2 : kNaN;
  c.bend_mm2 = std::isfinite(before) && std::isfinite(after) ? 0.5 * (before + after)
               : std::isfinite(before)                       ? before
               : std::isfinite(after)                        ? after
                                                             : 0.0;
  return c;
}

double SurfaceBelow::CenterAt(double path) const {
  std::size_t i = 0, j = 0;
  double w = 0;
  if (!Neighbours(path, i, j, w, nullptr)) return kNaN;
  return (1 - w) * below_[i].center_x_mm + w * below_[j].center_x_mm;
}

namespace {

// The finite points of p, increasing in x (kept in their order where they
// increase, sorted where not).
void KeepValid(StoredProfile& p) {
  std::size_t n = 0;
  bool increasing = true;
  float before = -std::numeric_limits<float>::infinity();
  for (std::size_t j = 0; j < p.x_mm.size(); ++j) {
    const float x = p.x_mm[j], z = p.z_mm[j];
    const bool keep = std::isfinite(x) && std::isfinite(z);
    p.x_mm[n] = x, p.z_mm[n] = z;
    increasing = increasing && (!keep || before < x);
    before = keep ? x : before;
    n += keep;
  }
  p.x_mm.resize(n), p.z_mm.resize(n);
  if (increasing) return;
  std::vector<std::pair<float, float>> points;
  for (std::size_t j = 0; j < n; ++j) points.emplace_back(p.x_mm[j], p.z_mm[j]);
  std::sort(points.begin(), points.end());
  for (std::size_t j = 0; j < n; ++j) p.x_mm[j] = points[j].first, p.z_mm[j] = points[j].second;
}

}  // namespace

// A profile's valid points moved into the bed frame, increasing in x (a
// sensor's usually are: sorted only where they are not).
StoredProfile InBedFrame(const ProfileView& v, double path, double frame_x, double frame_z, SurfaceBelow& below) {
  StoredProfile p;
  p.path_mm = path;
  p.x_mm = below.Spare(), p.z_mm = below.Spare();
  const std::size_t points = v.x_mm.size();
  p.x_mm.resize(points), p.z_mm.resize(points);
  // Every point moved; a sensor's complete profile (every point finite, x
  // increasing) is then taken as it is, checked without branches.
  int off =
      ActivePartKernel().to_bed(v.x_mm.data(), v.z_mm.data(), points, frame_x, frame_z, p.x_mm.data(), p.z_mm.data());
  for (std::size_t j = 1; j < points; ++j) off |= !(p.x_mm[j - 1] < p.x_mm[j]);
  if (off) KeepValid(p);
  p.spacing_mm = PointSpacingMm(p.x_mm);
  return p;
}

}  // namespace bead::part
