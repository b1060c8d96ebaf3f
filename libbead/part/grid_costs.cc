#include "libbead/part/grid_costs.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "libbead/part/part_kernel.h"

namespace bead::part {

namespace {

GridShared SharedAt(double noise2, double cap, double dx) {
  return {static_cast<float>(noise2), static_cast<float>(cap), static_cast<float>(1.0 / dx)};
}

// A row the grid path can read: its values the measured points, with
// their variances.
bool PointsRow(const SurfaceRow* r) {
  return r && r->at_points && r->z_mm.size() >= 2 && r->variance.size() == r->z_mm.size() && r->dx_mm > 0.0;
}

}  // namespace

bool PointsOnGrid::Make(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below) {
  grid_ = &below;
  rows_[0] = below.row(0), rows_[1] = below.row(1);
  count_ = rows_[1] ? 2 : 1;
  const bool rows_ok =
      PointsRow(rows_[0]) &&
      (count_ == 1 || (PointsRow(rows_[1]) && std::abs(rows_[1]->dx_mm - rows_[0]->dx_mm) <= 1e-6 * rows_[0]->dx_mm));
  if (!rows_ok || x.size() < 2) return count_ = 0, false;
  dx_mm_ = rows_[0]->dx_mm;
  unit_ = true;
  for (int r = 0; r < count_; ++r)
    unit_ =
        unit_ && std::all_of(rows_[r]->variance.begin(), rows_[r]->variance.end(), [](float v) { return v == 1.0f; });
  const double last = std::round((x.back() - x.front()) / dx_mm_);
  if (!(last >= 1.0) || last + 1.0 >= static_cast<double>(kMaxGridPoints)) return count_ = 0, false;
  x0_mm_ = x.front();
  if (!PlaceOnGrid(x, z, dx_mm_, static_cast<std::size_t>(last) + 1, z_)) return count_ = 0, false;
  counted_.resize(z_.size() + 1);
  if (z_.size() == x.size()) {  // every grid point measured
    std::iota(counted_.begin(), counted_.end(), 0);
    return true;
  }
  counted_[0] = 0;
  for (std::size_t i = 0; i < z_.size(); ++i) counted_[i + 1] = counted_[i] + !std::isnan(z_[i]);
  return true;
}

PointsOnGrid::Span PointsOnGrid::Inside(double s) const {
  Span span;
  span.rows.count = count_;
  span.rows.w = static_cast<float>(grid_->weight());
  span.rows.unit = unit_;
  // The intersection shrinks from every index, the union grows from none.
  span.begin = 0, span.end = std::ssize(z_);
  span.any_begin = std::ssize(z_), span.any_end = 0;
  for (int r = 0; r < count_; ++r) {
    const SurfaceRow& row = *rows_[r];
    const double c = (x0_mm_ - s - row.x0_mm) / dx_mm_, whole = std::floor(c);
    const auto k0 = static_cast<std::ptrdiff_t>(whole);
    span.rows.t[r] = static_cast<float>(c - whole);
    span.rows.z[r] = row.z_mm.data() + k0;  // index i reads values i + k0 and i + k0 + 1
    span.rows.v[r] = row.variance.data() + k0;
    const std::ptrdiff_t begin = std::max<std::ptrdiff_t>(0, -k0);
    const std::ptrdiff_t end = std::max(begin, std::min<std::ptrdiff_t>(std::ssize(z_), std::ssize(row.z_mm) - 1 - k0));
    span.begin = std::max(span.begin, begin), span.end = std::min(span.end, end);
    span.any_begin = std::min(span.any_begin, begin), span.any_end = std::max(span.any_end, end);
  }
  span.end = std::max(span.end, span.begin);
  span.any_end = std::max(span.any_end, span.any_begin);
  return span;
}

std::size_t PointsOnGrid::PointsIn(std::ptrdiff_t begin, std::ptrdiff_t end) const {
  if (end <= begin) return 0;
  return static_cast<std::size_t>(counted_[static_cast<std::size_t>(end)] - counted_[static_cast<std::size_t>(begin)]);
}

template <class F>
void PointsOnGrid::EachEdgePoint(double s, std::ptrdiff_t begin, std::ptrdiff_t end, const Span& in, F f) const {
  auto each = [&](std::ptrdiff_t from, std::ptrdiff_t to) {
    for (std::ptrdiff_t i = std::max(from, begin); i < std::min(to, end); ++i)
      if (!std::isnan(z_[static_cast<std::size_t>(i)]))
        f(i, grid_->SampleAt(x0_mm_ + static_cast<double>(i) * dx_mm_ - s));
  };
  each(in.any_begin, in.begin);
  each(in.end, in.any_end);
}

double PointsOnGrid::TruncatedCost(double s, double noise2, double cap, double lo, double hi) const {
  const auto first = std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil((lo - x0_mm_) / dx_mm_ - 1e-9)));
  const auto end = std::min<std::ptrdiff_t>(std::ssize(z_),
                                            static_cast<std::ptrdiff_t>(std::floor((hi - x0_mm_) / dx_mm_ + 1e-9)) + 1);
  if (end <= first) return 0.0;
  const Span in = Inside(s);
  const std::ptrdiff_t b = std::clamp(in.begin, first, end), e = std::clamp(in.end, b, end);
  const std::ptrdiff_t ab = std::clamp(in.any_begin, first, end), ae = std::clamp(in.any_end, ab, end);
  // Beyond every row: the surface below unknown, the cap.
  double cost = static_cast<double>(PointsIn(first, end) - PointsIn(ab, ae)) * cap;
  cost += kernel_->truncated(z_.data(), in.rows, b, e, SharedAt(noise2, cap, dx_mm_)).first;
  EachEdgePoint(s, first, end, in, [&](std::ptrdiff_t i, const SurfaceGrid::Sample& at) {
    const double d = z_[static_cast<std::size_t>(i)] - at.z;
    cost += std::isnan(d) ? cap : std::min(d * d / (noise2 * (1.0 + at.variance)), cap);
  });
  return cost;
}

PointsOnGrid::Local PointsOnGrid::LocalCost(double s, double noise2, double cap) const {
  const Span in = Inside(s);
  const std::ptrdiff_t n = std::ssize(z_);
  const GridSums sums = kernel_->local(z_.data(), in.rows, in.begin, in.end, SharedAt(noise2, cap, dx_mm_));
  Local l{sums.first + static_cast<double>(PointsIn(0, n) - PointsIn(in.any_begin, in.any_end)) * cap, sums.second,
          sums.third};
  EachEdgePoint(s, 0, n, in, [&](std::ptrdiff_t i, const SurfaceGrid::Sample& at) {
    const double d = z_[static_cast<std::size_t>(i)] - at.z, v = noise2 * (1.0 + at.variance), chi2 = d * d / v;
    if (!(chi2 < cap)) {
      l.cost += cap;
      return;
    }
    l.cost += chi2, l.gradient += 2.0 * d * at.slope / v, l.curvature += 2.0 * at.slope * at.slope / v;
  });
  return l;
}

PointsOnGrid::Agreement PointsOnGrid::Agree(double s, double tau, double feature_slope) const {
  const Span in = Inside(s);
  const float steep = static_cast<float>(feature_slope * dx_mm_);  // the rise over one grid step
  const GridSums sums = kernel_->agree(z_.data(), in.rows, in.begin, in.end, static_cast<float>(tau), steep);
  Agreement out;
  out.sum_d2 = sums.first;
  out.points = static_cast<int>(sums.second);
  out.features = static_cast<int>(sums.third);
  EachEdgePoint(s, 0, std::ssize(z_), in, [&](std::ptrdiff_t i, const SurfaceGrid::Sample& at) {
    const double d = z_[static_cast<std::size_t>(i)] - at.z;
    if (!(std::abs(d) <= tau)) return;
    out.sum_d2 += d * d, ++out.points, out.features += std::abs(at.slope) > feature_slope;
  });
  return out;
}

void PointsOnGrid::BelowAt(double s, std::vector<float>& z_below) const {
  const Span in = Inside(s);
  // Every grid point measured: the lattice is the points, written in place.
  const bool complete = static_cast<std::size_t>(counted_.back()) == z_.size();
  std::vector<float>& out = complete ? z_below : on_grid_;
  const auto n = std::ssize(z_);
  out.resize(z_.size());
  std::fill(out.begin(), out.begin() + std::clamp<std::ptrdiff_t>(in.begin, 0, n), NAN);
  std::fill(out.begin() + std::clamp<std::ptrdiff_t>(in.end, 0, n), out.end(), NAN);
  kernel_->below_at(in.rows, in.begin, in.end, out.data());
  EachEdgePoint(s, 0, n, in, [&](std::ptrdiff_t i, const SurfaceGrid::Sample& at) {
    out[static_cast<std::size_t>(i)] = static_cast<float>(at.z);
  });
  if (complete) return;
  z_below.resize(static_cast<std::size_t>(counted_.back()));
  for (std::size_t i = 0; i < z_.size(); ++i)
    if (!std::isnan(z_[i])) z_below[static_cast<std::size_t>(counted_[i])] = on_grid_[i];
}

}  // namespace bead::part
