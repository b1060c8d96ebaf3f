#include "libbead/part/grid_costs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "libbead/profile/vec8.h"

namespace bead::part {
namespace {

using vec::V8;

template <class T>
T Broadcast(float v) {
  if constexpr (std::is_same_v<T, float>)
    return v;
  else
    return vec::Splat(v);
}

// What every point's term shares at one shift.
struct Shared {
  float t, t0sq, tsq;  // the fraction between two grid values, (1 - t)^2 and t^2
  float noise2, cap, inv_dx;
};

template <class T>
struct Sums {
  T cost{}, gradient{}, curvature{};
};

// One point's (or eight points') terms: the surface below a fraction t
// from a0 to a1 (variances v0, v1; SurfaceRow::SampleAt for points on
// the grid), the gain d = zn - z_below in its variance; a missing new
// point (NaN) counts nothing, a missing surface below the cap.
template <bool kLocal, class T>
inline void Add(T zn, T a0, T a1, T v0, T v1, const Shared& c, Sums<T>& s) {
  const T zb = a0 + Broadcast<T>(c.t) * (a1 - a0);
  const T var = Broadcast<T>(c.t0sq) * v0 + Broadcast<T>(c.tsq) * v1;
  const T d = zn - zb;
  const T vv = Broadcast<T>(c.noise2) * (Broadcast<T>(1.0f) + var);
  const T chi = d * d / vv, cap = Broadcast<T>(c.cap), zero = Broadcast<T>(0.0f);
  const auto present = zn == zn, under = chi < cap;
  s.cost += present ? (under ? chi : cap) : zero;
  if constexpr (kLocal) {
    const T g = (a1 - a0) * Broadcast<T>(c.inv_dx);
    const auto fits = present & under;
    s.gradient += fits ? Broadcast<T>(2.0f) * d * g / vv : zero;
    s.curvature += fits ? Broadcast<T>(2.0f) * g * g / vv : zero;
  }
}

// One point's (or eight points') part in where the surfaces agree: its
// squared gain where |gain| <= limit, and whether the surface below rises
// more than `steep` over the grid step there (sums: cost, gradient and
// curvature hold the squares, the points and the steep ones).
template <class T>
inline void AddAgreement(T zn, T a0, T a1, float t, float limit, float steep, Sums<T>& s) {
  const T d = zn - (a0 + Broadcast<T>(t) * (a1 - a0)), zero = Broadcast<T>(0.0f), one = Broadcast<T>(1.0f);
  const T ad = d < zero ? -d : d, rise = a1 < a0 ? a0 - a1 : a1 - a0;
  const auto agree = ad <= Broadcast<T>(limit);  // false where either is NaN
  s.cost += agree ? d * d : zero;
  s.gradient += agree ? one : zero;
  s.curvature += (agree & (rise > Broadcast<T>(steep))) ? one : zero;
}

// The terms of indices [begin, end): zn the new points, a and v the row's
// values and variances moved so that index i falls between a[i] and a[i + 1].
template <bool kLocal>
Sums<double> Pass(const float* zn, const float* a, const float* v, std::ptrdiff_t begin, std::ptrdiff_t end,
                  const Shared& c) {
  Sums<V8> wide;
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8)
    Add<kLocal>(vec::Load(zn + i), vec::Load(a + i), vec::Load(a + i + 1), vec::Load(v + i), vec::Load(v + i + 1), c,
                wide);
  Sums<float> narrow;
  for (; i < end; ++i) Add<kLocal>(zn[i], a[i], a[i + 1], v[i], v[i + 1], c, narrow);
  Sums<double> out;
  out.cost = static_cast<double>(vec::Sum(wide.cost)) + narrow.cost;
  out.gradient = static_cast<double>(vec::Sum(wide.gradient)) + narrow.gradient;
  out.curvature = static_cast<double>(vec::Sum(wide.curvature)) + narrow.curvature;
  return out;
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
  const Shared c{in.t,
                 (1 - in.t) * (1 - in.t),
                 in.t * in.t,
                 static_cast<float>(noise2),
                 static_cast<float>(cap),
                 static_cast<float>(1.0 / dx)};
  const Sums<double> sums = Pass<false>(z_.data(), row_->z_mm.data() + in.k0, row_->variance.data() + in.k0, b, e, c);
  return sums.cost + outside * cap;
}

PointsOnRow::Local PointsOnRow::LocalCost(double s, double noise2, double cap) const {
  const Span in = Inside(s);
  const double outside = static_cast<double>(PointsIn(0, std::ssize(z_)) - PointsIn(in.begin, in.end));
  const Shared c{in.t,
                 (1 - in.t) * (1 - in.t),
                 in.t * in.t,
                 static_cast<float>(noise2),
                 static_cast<float>(cap),
                 static_cast<float>(1.0 / row_->dx_mm)};
  const Sums<double> sums =
      Pass<true>(z_.data(), row_->z_mm.data() + in.k0, row_->variance.data() + in.k0, in.begin, in.end, c);
  return {sums.cost + outside * cap, sums.gradient, sums.curvature};
}

PointsOnRow::Agreement PointsOnRow::Agree(double s, double tau, double feature_slope) const {
  const Span in = Inside(s);
  const float* a = row_->z_mm.data() + in.k0;
  const float limit = static_cast<float>(tau);
  const float steep = static_cast<float>(feature_slope * row_->dx_mm);  // the rise over one grid step
  Sums<V8> wide;  // cost: the squared gains; gradient: the points; curvature: those where the surface slopes
  Sums<float> narrow;
  std::ptrdiff_t i = in.begin;
  for (; i + 8 <= in.end; i += 8)
    AddAgreement(vec::Load(z_.data() + i), vec::Load(a + i), vec::Load(a + i + 1), in.t, limit, steep, wide);
  for (; i < in.end; ++i) AddAgreement(z_[static_cast<std::size_t>(i)], a[i], a[i + 1], in.t, limit, steep, narrow);
  Agreement out;
  out.sum_d2 = static_cast<double>(vec::Sum(wide.cost)) + narrow.cost;
  out.points = static_cast<int>(vec::Sum(wide.gradient) + narrow.gradient);
  out.features = static_cast<int>(vec::Sum(wide.curvature) + narrow.curvature);
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
