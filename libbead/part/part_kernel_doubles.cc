// A part profile's loops in doubles, four a register (part_kernel.h: the
// hidden groove's ellipse, the held top's sums, the surface below at
// places), built once per instruction set as part_kernel.cc is.
#include "libbead/part/part_kernel_doubles.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace bead::part::BEAD_KERNEL {
namespace {

// Four doubles a register (AVX2: one; the baseline: two).
typedef double V4D __attribute__((vector_size(32)));
V4D LoadD(const double* p) {
  V4D v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
V4D SplatD(double x) { return V4D{} + x; }
double SumD(V4D v) { return (v[0] + v[1]) + (v[2] + v[3]); }

V4D SqrtOf(V4D v) {
#if defined(__AVX__)
  return __builtin_ia32_sqrtpd256(v);
#elif defined(__SSE2__)
  typedef double V2D __attribute__((vector_size(16)));
  const V2D lo = __builtin_ia32_sqrtpd(V2D{v[0], v[1]}), hi = __builtin_ia32_sqrtpd(V2D{v[2], v[3]});
  return V4D{lo[0], lo[1], hi[0], hi[1]};
#else
  for (int i = 0; i < 4; ++i) v[i] = std::sqrt(v[i]);
  return v;
#endif
}
double SqrtOf(double v) { return std::sqrt(v); }
template <class T>
T BroadcastD(double v) {
  if constexpr (std::is_same_v<T, double>)
    return v;
  else
    return SplatD(v);
}

// One point's (or four points') part in the ellipse's sums: the sensor
// sees the ellipse's top where it stands above the surface below, the
// surface below elsewhere; the derivatives hidden_groove.cc's Residuals
// gives, zero where the surface below is seen.
template <class T>
struct EllipseLanes {
  T rss{}, jtj[10]{}, jtr[4]{};
};

// kHeld: the aspect held, b's column zero: its terms not summed (their
// sums stay exactly 0).
template <bool kHeld, class T>
inline void AddEllipse(T x, T z, T old, const EllipseAt& e, EllipseLanes<T>& s) {
  const T zero = BroadcastD<T>(0.0), one = BroadcastD<T>(1.0);
  const T u = (x - BroadcastD<T>(e.x0)) / BroadcastD<T>(e.a);
  const T q = one - u * u;
  const T sv = q > zero ? SqrtOf(q > zero ? q : zero) : zero;  // 0 off the ellipse (|u| >= 1)
  const T top = BroadcastD<T>(e.z0) + BroadcastD<T>(e.b) * sv;
  const auto seen = (sv > zero) & (top > old);
  const T r = (seen ? top : old) - z;
  s.rss += r * r;
  const T sd = sv > BroadcastD<T>(0.02) ? sv : BroadcastD<T>(0.02);
  const T k = BroadcastD<T>(e.b) / (BroadcastD<T>(e.a) * sd);
  const T by_a = kHeld ? k * u * u + BroadcastD<T>(e.aspect) * sv : k * u * u;
  const T g[4] = {seen ? k * u : zero, seen ? one : zero, seen ? by_a : zero, kHeld ? zero : (seen ? sv : zero)};
  constexpr int kParams = kHeld ? 3 : 4;
  int n = 0;
  for (int i = 0; i < kParams; ++i) {
    for (int j = i; j < kParams; ++j) s.jtj[n + j - i] += g[i] * g[j];
    n += 4 - i;
    s.jtr[i] += g[i] * r;
  }
}

template <bool kHeld>
EllipseSums EllipseOver(const double* x, const double* z, const double* old, std::size_t lo, std::size_t hi,
                        const EllipseAt& e) {
  EllipseLanes<V4D> wide;
  std::size_t i = lo;
  for (; i + 4 <= hi; i += 4) AddEllipse<kHeld>(LoadD(x + i), LoadD(z + i), LoadD(old + i), e, wide);
  EllipseLanes<double> narrow;
  for (; i < hi; ++i) AddEllipse<kHeld>(x[i], z[i], old[i], e, narrow);
  EllipseSums out;
  out.rss = SumD(wide.rss) + narrow.rss;
  for (int k = 0; k < 10; ++k) out.jtj[k] = SumD(wide.jtj[k]) + narrow.jtj[k];
  for (int k = 0; k < 4; ++k) out.jtr[k] = SumD(wide.jtr[k]) + narrow.jtr[k];
  return out;
}

}  // namespace

EllipseSums Ellipse(const double* x, const double* z, const double* old, std::size_t lo, std::size_t hi,
                    const EllipseAt& e) {
  return e.aspect == e.aspect ? EllipseOver<true>(x, z, old, lo, hi, e) : EllipseOver<false>(x, z, old, lo, hi, e);
}

namespace {

// One top point's (or four points') s(u) from the table: |u| capped at its
// reach, the entry below and the fraction to the next.
template <class T>
struct TopLanes {
  T z1{}, zz{}, s1{}, s2{}, zs{};
};
inline void AddTop(double x, double z, double x0, double per_a, const TopTable& t, double per_u, TopLanes<double>& s) {
  const double u = (x - x0) * per_a, f = std::min(u < 0.0 ? -u : u, t.reach) * per_u;
  const int k = std::min(static_cast<int>(f), t.last_entry - 1);
  const double frac = f - k, sv = t.s[k] + frac * (t.s[k + 1] - t.s[k]);
  s.z1 += z, s.zz += z * z, s.s1 += sv, s.s2 += sv * sv, s.zs += z * sv;
}

}  // namespace

TopSums5 Top(const double* x, const double* z, std::size_t lo, std::size_t hi, double x0, double per_a,
             const TopTable& t) {
  // (The scalar's Locate: its scale a double constant, entries / reach.)
  const double per_u = t.last_entry / t.reach;
  TopLanes<V4D> wide;
  std::size_t i = lo;
  const V4D vx0 = SplatD(x0), vper_a = SplatD(per_a), reach = SplatD(t.reach), vper_u = SplatD(per_u);
  typedef int V4I __attribute__((vector_size(16)));
  const V4I most = V4I{} + (t.last_entry - 1);
  for (; i + 4 <= hi; i += 4) {
    const V4D u = (LoadD(x + i) - vx0) * vper_a, zv = LoadD(z + i);
    const V4D a = u < SplatD(0.0) ? -u : u, f = (a < reach ? a : reach) * vper_u;
    V4I k = __builtin_convertvector(f, V4I);
    k = k < most ? k : most;
    const V4D frac = f - __builtin_convertvector(k, V4D);
#if defined(__AVX2__)
    // (The masked form: the plain one's undefined start warns in GCC 12.)
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    const V4D s0 = (V4D)_mm256_mask_i32gather_pd(_mm256_setzero_pd(), t.s, (__m128i)k, all, 8);
    const V4D s1 = (V4D)_mm256_mask_i32gather_pd(_mm256_setzero_pd(), t.s + 1, (__m128i)k, all, 8);
#else
    const V4D s0{t.s[k[0]], t.s[k[1]], t.s[k[2]], t.s[k[3]]};
    const V4D s1{t.s[k[0] + 1], t.s[k[1] + 1], t.s[k[2] + 1], t.s[k[3] + 1]};
#endif
    const V4D sv = s0 + frac * (s1 - s0);
    wide.z1 += zv, wide.zz += zv * zv, wide.s1 += sv, wide.s2 += sv * sv, wide.zs += zv * sv;
  }
  TopLanes<double> narrow;
  for (; i < hi; ++i) AddTop(x[i], z[i], x0, per_a, t, per_u, narrow);
  return {SumD(wide.z1) + narrow.z1, SumD(wide.zz) + narrow.zz, SumD(wide.s1) + narrow.s1, SumD(wide.s2) + narrow.s2,
          SumD(wide.zs) + narrow.zs};
}

namespace {

// One row's value at x (four places): linear between the values around
// its index, NaN off the row (a NaN value stands for itself).
double RowAt(double x, const RowsAt& r, int i) {
  const double u = (x - r.shift - r.x0[i]) * r.per_mm[i];
  if (!(u >= 0.0) || !(u <= static_cast<double>(r.size[i]) - 1.0) || r.size[i] < 2) return NAN;
  const std::size_t k = std::min(static_cast<std::size_t>(u), r.size[i] - 2);
  const double t = u - static_cast<double>(k);
  return r.z[i][k] + t * (static_cast<double>(r.z[i][k + 1]) - r.z[i][k]);
}
V4D RowAt(V4D x, const RowsAt& r, int i) {
  const V4D u = (x - r.shift - r.x0[i]) * r.per_mm[i];
  const auto on = (u >= 0.0) & (u <= static_cast<double>(r.size[i]) - 1.0);
  const V4D last = V4D{} + (static_cast<double>(r.size[i]) - 2.0);
  const V4D within = on ? (u < last ? u : last) : V4D{};
  typedef int V4I __attribute__((vector_size(16)));
  const V4I k = __builtin_convertvector(within, V4I);
  const V4D t = u - __builtin_convertvector(k, V4D);
  const float* z = r.z[i];
  const V4D a{z[k[0]], z[k[1]], z[k[2]], z[k[3]]}, b{z[k[0] + 1], z[k[1] + 1], z[k[2] + 1], z[k[3] + 1]};
  return on ? a + t * (b - a) : V4D{} + NAN;
}

// The rows blended by SurfaceGrid::Blend's rule (surface_below.h), four
// places a register: both known, (1 - w) a + w b; one, that one.
template <class T>
T Blend(T a, T b, double w) {
  const auto a_known = a == a;
  const auto b_known = b == b;
  return (a_known & b_known) ? (1 - w) * a + w * b : (b_known ? b : a);
}

}  // namespace

void RowsAtPlaces(const double* x, std::size_t n, const RowsAt& r, double* out) {
  if (r.count == 0 || r.size[0] < 2) {
    for (std::size_t i = 0; i < n; ++i) out[i] = NAN;
    return;
  }
  const bool two = r.count == 2 && r.size[1] >= 2;  // (a second row of one value is never known)
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const V4D xs = LoadD(x + i), a = RowAt(xs, r, 0);
    const V4D v = two ? Blend(a, RowAt(xs, r, 1), r.w) : a;
    std::memcpy(out + i, &v, sizeof v);
  }
  for (; i < n; ++i) {
    const double a = RowAt(x[i], r, 0);
    out[i] = two ? Blend(a, RowAt(x[i], r, 1), r.w) : a;
  }
}

}  // namespace bead::part::BEAD_KERNEL
