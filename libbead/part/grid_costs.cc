#include "libbead/part/grid_costs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "libbead/part/part_kernel.h"

namespace bead::part {

#ifdef BEAD_AVX2_KERNEL
namespace avx2 {
const PartKernel& PartKernelBuild();
}  // namespace avx2
#endif
namespace baseline {
const PartKernel& PartKernelBuild();
}  // namespace baseline

const PartKernel& BaselinePartKernel() { return baseline::PartKernelBuild(); }

const PartKernel& ActivePartKernel() {
#ifdef BEAD_AVX2_KERNEL
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) return avx2::PartKernelBuild();
#endif
  return BaselinePartKernel();
}

namespace {

GridShared SharedAt(float t, double noise2, double cap, double dx) {
  return {
      t, (1 - t) * (1 - t), t * t, static_cast<float>(noise2), static_cast<float>(cap), static_cast<float>(1.0 / dx)};
}

}  // namespace

bool PointsOnRow::Make(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below) {
  row_ = below.single_row();
  if (!row_ || !row_->at_points || x.size() < 2 || row_->z_mm.size() < 2 ||
      row_->variance.size() != row_->z_mm.size() || !(row_->dx_mm > 0.0)) {
    row_ = nullptr;
    return false;
  }
  const double dx = row_->dx_mm, last = std::round((x.back() - x.front()) / dx);
  if (!(last >= 1.0) || last + 1.0 >= static_cast<double>(kMaxGridPoints)) return row_ = nullptr, false;
  x0_mm_ = x.front();
  z_.assign(static_cast<std::size_t>(last) + 1, NAN);
  const double per_mm = 1.0 / dx;
  for (std::size_t j = 0; j < x.size(); ++j) {
    // x increases from x0: u >= 0 but for rounding, and the nearest whole
    // number is the truncation of u + 1/2.
    const double u = (x[j] - x0_mm_) * per_mm;
    const auto m = static_cast<int64_t>(u + 0.5);
    if (std::abs(u - static_cast<double>(m)) > 0.01 || m < 0 || static_cast<double>(m) > last)
      return row_ = nullptr, false;
    z_[static_cast<std::size_t>(m)] = z[j];
  }
  counted_.assign(z_.size() + 1, 0);
  for (std::size_t i = 0; i < z_.size(); ++i) counted_[i + 1] = counted_[i] + !std::isnan(z_[i]);
  return true;
}

PointsOnRow::Span PointsOnRow::Inside(double s) const {
  const double c = (x0_mm_ - s - row_->x0_mm) / row_->dx_mm, whole = std::floor(c);
  Span span;
  span.k0 = static_cast<std::ptrdiff_t>(whole);
  span.t = static_cast<float>(c - whole);
  // Index i samples between row values i + k0 and i + k0 + 1.
  span.begin = std::max<std::ptrdiff_t>(0, -span.k0);
  span.end = std::min<std::ptrdiff_t>(std::ssize(z_), std::ssize(row_->z_mm) - 1 - span.k0);
  span.end = std::max(span.end, span.begin);
  return span;
}

std::size_t PointsOnRow::PointsIn(std::ptrdiff_t begin, std::ptrdiff_t end) const {
  if (end <= begin) return 0;
  return static_cast<std::size_t>(counted_[static_cast<std::size_t>(end)] - counted_[static_cast<std::size_t>(begin)]);
}

double PointsOnRow::TruncatedCost(double s, double noise2, double cap, double lo, double hi) const {
  const double dx = row_->dx_mm;
  const auto first = std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil((lo - x0_mm_) / dx - 1e-9)));
  const auto end =
      std::min<std::ptrdiff_t>(std::ssize(z_), static_cast<std::ptrdiff_t>(std::floor((hi - x0_mm_) / dx + 1e-9)) + 1);
  if (end <= first) return 0.0;
  const Span in = Inside(s);
  const std::ptrdiff_t b = std::clamp(in.begin, first, end), e = std::clamp(in.end, b, end);
  const double outside = static_cast<double>(PointsIn(first, end) - PointsIn(b, e));
  const GridSums sums = kernel_->truncated(z_.data(), row_->z_mm.data() + in.k0, row_->variance.data() + in.k0, b, e,
                                           SharedAt(in.t, noise2, cap, dx));
  return sums.first + outside * cap;
}

PointsOnRow::Local PointsOnRow::LocalCost(double s, double noise2, double cap) const {
  const Span in = Inside(s);
  const double outside = static_cast<double>(PointsIn(0, std::ssize(z_)) - PointsIn(in.begin, in.end));
  const GridSums sums = kernel_->local(z_.data(), row_->z_mm.data() + in.k0, row_->variance.data() + in.k0, in.begin,
                                       in.end, SharedAt(in.t, noise2, cap, row_->dx_mm));
  return {sums.first + outside * cap, sums.second, sums.third};
}

PointsOnRow::Agreement PointsOnRow::Agree(double s, double tau, double feature_slope) const {
  const Span in = Inside(s);
  const float* a = row_->z_mm.data() + in.k0;
  const float limit = static_cast<float>(tau);
  const float steep = static_cast<float>(feature_slope * row_->dx_mm);  // the rise over one grid step
  const GridSums sums = kernel_->agree(z_.data(), a, in.begin, in.end, in.t, limit, steep);
  Agreement out;
  out.sum_d2 = sums.first;
  out.points = static_cast<int>(sums.second);
  out.features = static_cast<int>(sums.third);
  return out;
}

void PointsOnRow::BelowAt(double s, std::vector<float>& z_below) const {
  const Span in = Inside(s);
  const float* a = row_->z_mm.data() + in.k0;
  const float t = in.t;
  on_grid_.assign(z_.size(), NAN);
  for (std::ptrdiff_t i = in.begin; i < in.end; ++i)
    on_grid_[static_cast<std::size_t>(i)] = a[i] + t * (a[i + 1] - a[i]);
  z_below.resize(static_cast<std::size_t>(counted_.back()));
  for (std::size_t i = 0; i < z_.size(); ++i)
    if (!std::isnan(z_[i])) z_below[static_cast<std::size_t>(counted_[i])] = on_grid_[i];
}

}  // namespace bead::part
