// A part profile's loops, built once per instruction set (part_kernel.h).
#include "libbead/part/part_kernel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "libbead/core/float_bits.h"
#include "libbead/profile/vec8.h"
#include "libbead/profile/vec_sort.h"

namespace bead::part::BEAD_KERNEL {
namespace {

using vec::V8;

template <class T>
T Broadcast(float v) {
  if constexpr (std::is_same_v<T, float>)
    return v;
  else
    return vec::Splat(v);
}

template <class T>
struct Sums {
  T first{}, second{}, third{};
};

// The surface below at one index (or eight): z, its variance, and its
// rise over the grid step there (the slope times dx).
template <class T>
struct Below {
  T z, var, rise;
};

template <class T>
inline T At(const float* p, std::ptrdiff_t i) {
  if constexpr (std::is_same_v<T, float>)
    return p[i];
  else
    return vec::Load(p + i);
}

// One row's sample a fraction t of the way from value i to value i + 1.
template <class T>
inline Below<T> OneRow(const float* z, const float* v, float t, std::ptrdiff_t i) {
  const T a0 = At<T>(z, i), a1 = At<T>(z, i + 1), tt = Broadcast<T>(t);
  const T var = Broadcast<T>((1 - t) * (1 - t)) * At<T>(v, i) + Broadcast<T>(t * t) * At<T>(v, i + 1);
  return {a0 + tt * (a1 - a0), var, a1 - a0};
}

// The rows' sample at index i: one row, or two blended as SurfaceGrid
// blends them (where one is not known, the other stands for both).
template <bool kTwo, class T>
inline Below<T> Sample(const GridRows& r, std::ptrdiff_t i) {
  const Below<T> a = OneRow<T>(r.z[0], r.v[0], r.t[0], i);
  if constexpr (!kTwo) {
    return a;
  } else {
    const Below<T> b = OneRow<T>(r.z[1], r.v[1], r.t[1], i);
    const T w = Broadcast<T>(r.w), w0 = Broadcast<T>(1.0f - r.w);
    // Each declared alone: for one float, a comparison is a bool and two
    // combined an int; for eight, both are the lanes' mask.
    const auto a_known = a.z == a.z;
    const auto b_known = b.z == b.z;
    const auto both = a_known & b_known;
    return {both ? w0 * a.z + w * b.z : (b_known ? b.z : a.z),
            both ? w0 * w0 * a.var + w * w * b.var : (b_known ? b.var : a.var),
            both ? w0 * a.rise + w * b.rise : (b_known ? b.rise : a.rise)};
  }
}

// One point's (or eight points') terms over the surface below there: the
// gain d = zn - z_below in its variance; a missing new point (NaN) counts
// nothing, a missing surface below the cap. first: the cost; with kLocal,
// second and third: the gradient and curvature in s over the points under
// the cap (d(gain)/ds is the slope of the surface below).
template <bool kLocal, class T>
inline void Add(T zn, const Below<T>& b, const GridShared& c, Sums<T>& s) {
  const T d = zn - b.z;
  const T vv = Broadcast<T>(c.noise2) * (Broadcast<T>(1.0f) + b.var);
  const T chi = d * d / vv, cap = Broadcast<T>(c.cap), zero = Broadcast<T>(0.0f);
  const auto present = zn == zn, under = chi < cap;
  s.first += present ? (under ? chi : cap) : zero;
  if constexpr (kLocal) {
    const T g = b.rise * Broadcast<T>(c.inv_dx);
    const auto fits = present & under;
    s.second += fits ? Broadcast<T>(2.0f) * d * g / vv : zero;
    s.third += fits ? Broadcast<T>(2.0f) * g * g / vv : zero;
  }
}

// One point's (or eight points') part in where the surfaces agree: its
// squared gain where |gain| <= limit (first), one (second), and one where
// the surface below rises more than `steep` over the grid step (third).
template <class T>
inline void AddAgreement(T zn, const Below<T>& b, float limit, float steep, Sums<T>& s) {
  const T d = zn - b.z, zero = Broadcast<T>(0.0f), one = Broadcast<T>(1.0f);
  const T ad = d < zero ? -d : d, rise = b.rise < zero ? -b.rise : b.rise;
  const auto agree = ad <= Broadcast<T>(limit);  // false where either is NaN
  s.first += agree ? d * d : zero;
  s.second += agree ? one : zero;
  s.third += (agree & (rise > Broadcast<T>(steep))) ? one : zero;
}

GridSums Total(const Sums<V8>& wide, const Sums<float>& narrow) {
  return {static_cast<double>(vec::Sum(wide.first)) + narrow.first,
          static_cast<double>(vec::Sum(wide.second)) + narrow.second,
          static_cast<double>(vec::Sum(wide.third)) + narrow.third};
}

template <bool kLocal, bool kTwo>
GridSums Pass(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c) {
  Sums<V8> wide;
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8) Add<kLocal>(vec::Load(zn + i), Sample<kTwo, V8>(r, i), c, wide);
  Sums<float> narrow;
  for (; i < end; ++i) Add<kLocal>(zn[i], Sample<kTwo, float>(r, i), c, narrow);
  return Total(wide, narrow);
}

GridSums Truncated(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c) {
  return r.count == 2 ? Pass<false, true>(zn, r, begin, end, c) : Pass<false, false>(zn, r, begin, end, c);
}

GridSums Local(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c) {
  return r.count == 2 ? Pass<true, true>(zn, r, begin, end, c) : Pass<true, false>(zn, r, begin, end, c);
}

template <bool kTwo>
GridSums AgreePass(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, float limit,
                   float steep) {
  Sums<V8> wide;
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8) AddAgreement(vec::Load(zn + i), Sample<kTwo, V8>(r, i), limit, steep, wide);
  Sums<float> narrow;
  for (; i < end; ++i) AddAgreement(zn[i], Sample<kTwo, float>(r, i), limit, steep, narrow);
  return Total(wide, narrow);
}

GridSums Agree(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, float limit, float steep) {
  return r.count == 2 ? AgreePass<true>(zn, r, begin, end, limit, steep)
                      : AgreePass<false>(zn, r, begin, end, limit, steep);
}

template <bool kTwo>
void BelowPass(const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, float* out) {
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8) vec::Store(out + i, Sample<kTwo, V8>(r, i).z);
  for (; i < end; ++i) out[i] = Sample<kTwo, float>(r, i).z;
}

void BelowAt(const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, float* out) {
  if (r.count == 2)
    BelowPass<true>(r, begin, end, out);
  else
    BelowPass<false>(r, begin, end, out);
}

void SecondDifferences(const float* z, std::size_t n, float* out) {
  std::size_t i = 0;
  for (; i + 10 <= n; i += 8) {
    const V8 a = vec::Load(z + i), b = vec::Load(z + i + 1), c = vec::Load(z + i + 2);
    vec::Store(out + i, vec::Abs((a - b) + (c - b)));
  }
  for (; i + 2 < n; ++i) out[i] = std::abs((z[i] - z[i + 1]) + (z[i + 2] - z[i + 1]));
}

std::size_t Band(const float* v, std::size_t n, float lo, float hi, float* band, std::size_t& below) {
  const V8 low = vec::Splat(lo), high = vec::Splat(hi);
  vec::M8 under{};
  std::size_t in = 0, i = 0;
  for (; i + 8 <= n; i += 8) {
    const V8 x = vec::Load(v + i);
    const int bits = vec::Bits((x >= low) & (x < high));
    vec::Store(band + in, vec::Pack(x, vec::PackIndex(bits)));
    in += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(bits)));
    under -= x < low;  // true lanes are -1
  }
  below = static_cast<std::size_t>(vec::SumInt(under));
  for (; i < n; ++i) {
    band[in] = v[i];
    in += v[i] >= lo && v[i] < hi;
    below += v[i] < lo;
  }
  return in;
}

// The k-th smallest of n values (k < n <= 8 R), by sorting them in R
// registers (the rest +infinity) with the bitonic network.
template <int R>
float SortedKth(const float* v, std::size_t n, std::size_t k) {
  alignas(32) float padded[8 * R];
  for (std::size_t i = 0; i < 8 * R; ++i) padded[i] = i < n ? v[i] : __builtin_inff();
  V8 r[R];
  for (int i = 0; i < R; ++i) r[i] = vec::Load(padded + 8 * i);
  vec::BitonicSort<R>(r);
  return r[k / 8][k % 8];
}

float Kth(float* v, std::size_t n, std::size_t k) {
  if (n <= 64) return SortedKth<8>(v, n, k);
  if (n <= 128) return SortedKth<16>(v, n, k);
  std::nth_element(v, v + k, v + n);
  return v[k];
}

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

EllipseSums Ellipse(const double* x, const double* z, const double* old, std::size_t lo, std::size_t hi,
                    const EllipseAt& e) {
  return e.aspect == e.aspect ? EllipseOver<true>(x, z, old, lo, hi, e) : EllipseOver<false>(x, z, old, lo, hi, e);
}

// (float)(x + frame) in doubles: one rounding, no product to contract,
// so the builds agree bit for bit. NaN or infinity told by the bits
// (core/float_bits.h: this build's associative math folds v - v to 0).
bool ToBed(const float* x, const float* z, std::size_t n, double frame_x, double frame_z, float* ox, float* oz) {
  uint32_t off = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto xi = static_cast<float>(static_cast<double>(x[i]) + frame_x);
    const auto zi = static_cast<float>(static_cast<double>(z[i]) + frame_z);
    ox[i] = xi, oz[i] = zi;
    off |= static_cast<uint32_t>(!IsFiniteBits(xi)) | static_cast<uint32_t>(!IsFiniteBits(zi));
  }
  return off != 0;
}

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

// The rows blended: both known, (1 - w) a + w b; one, that one.
template <class T>
T Blend(T a, T b, double w) {
  const auto a_known = a == a;
  const auto b_known = b == b;
  return (a_known & b_known) ? (1 - w) * a + w * b : (b_known ? b : a);
}

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

#define BEAD_STRINGIFY_(x) #x
#define BEAD_STRINGIFY(x) BEAD_STRINGIFY_(x)
constexpr PartKernel kPartKernel{BEAD_STRINGIFY(BEAD_KERNEL),
                                 Truncated,
                                 Local,
                                 Agree,
                                 BelowAt,
                                 SecondDifferences,
                                 Band,
                                 Kth,
                                 Ellipse,
                                 ToBed,
                                 Top,
                                 RowsAtPlaces};

}  // namespace

const PartKernel& PartKernelBuild() { return kPartKernel; }

}  // namespace bead::part::BEAD_KERNEL
