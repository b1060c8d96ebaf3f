// A part profile's loops, built once per instruction set (part_kernel.h).
#include "libbead/part/part_kernel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "libbead/core/float_bits.h"
#include "libbead/part/part_kernel_doubles.h"
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

// The rows' sample at index i: one row, or two blended by SurfaceGrid::Blend's
// rule (surface_below.h; where one is not known, the other stands for both).
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

// Over rows of measured points (each value's variance one point's): a
// row's sample a fraction t of the way has (1 - t)^2 + t^2 of it, a
// constant of the row; two blended, (1 - w)^2 va + w^2 vb where both are
// known. A point's term over its variance is then over one point's noise
// variance and the surface below's: by one of three inverses, row a's
// alone, row b's alone or both blended.
struct UnitInverses {
  float a, b, ab;
};
UnitInverses Inverses(const GridRows& r, const GridShared& c, bool two) {
  const float va = (1 - r.t[0]) * (1 - r.t[0]) + r.t[0] * r.t[0];
  const float vb = two ? (1 - r.t[1]) * (1 - r.t[1]) + r.t[1] * r.t[1] : va;
  const float w = r.w, w0 = 1.0f - r.w;
  return {1.0f / (c.noise2 * (1.0f + va)), 1.0f / (c.noise2 * (1.0f + vb)),
          1.0f / (c.noise2 * (1.0f + w0 * w0 * va + w * w * vb))};
}

// Pass<false>'s cost over rows of unit variance (GridRows::unit): each
// point's term its squared gain times one of the three inverses, no v
// read, no division.
template <bool kTwo>
GridSums UnitTruncatedPass(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end,
                           const GridShared& c) {
  const UnitInverses u = Inverses(r, c, kTwo);
  const float w = r.w, w0 = 1.0f - r.w, inv_a = u.a, inv_b = u.b, inv_ab = u.ab;
  const float* const rz[2] = {r.z[0], r.z[1]};
  const float rt[2] = {r.t[0], r.t[1]}, cap_c = c.cap;
  const auto one = [&](auto tag, std::ptrdiff_t i, Sums<decltype(tag)>& sums) {
    using T = decltype(tag);
    const T a0 = At<T>(rz[0], i), a1 = At<T>(rz[0], i + 1);
    T z = a0 + Broadcast<T>(rt[0]) * (a1 - a0), inv = Broadcast<T>(inv_a);
    if constexpr (kTwo) {
      const T b0 = At<T>(rz[1], i), b1 = At<T>(rz[1], i + 1), zb = b0 + Broadcast<T>(rt[1]) * (b1 - b0);
      const auto a_known = z == z;
      const auto b_known = zb == zb;
      const auto both = a_known & b_known;
      z = both ? Broadcast<T>(w0) * z + Broadcast<T>(w) * zb : (b_known ? zb : z);
      inv = both ? Broadcast<T>(inv_ab) : (b_known ? Broadcast<T>(inv_b) : inv);
    }
    const T zi = At<T>(zn, i), d = zi - z, chi = d * d * inv, cap = Broadcast<T>(cap_c), zero = Broadcast<T>(0.0f);
    const auto present = zi == zi, under = chi < cap;
    sums.first += present ? (under ? chi : cap) : zero;
  };
  Sums<V8> wide;
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8) one(V8{}, i, wide);
  Sums<float> narrow;
  for (; i < end; ++i) one(0.0f, i, narrow);
  return Total(wide, narrow);
}

GridSums Truncated(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c) {
  if (r.unit)
    return r.count == 2 ? UnitTruncatedPass<true>(zn, r, begin, end, c)
                        : UnitTruncatedPass<false>(zn, r, begin, end, c);
  return r.count == 2 ? Pass<false, true>(zn, r, begin, end, c) : Pass<false, false>(zn, r, begin, end, c);
}

GridSums Local(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c) {
  return r.count == 2 ? Pass<true, true>(zn, r, begin, end, c) : Pass<true, false>(zn, r, begin, end, c);
}

// Local's sums over rows whose values are measured points (Inverses: no
// variance read, no division made per point); and the surface below and
// the gains (at least 0, NaN where either surface is) stored at every
// index.
template <bool kTwo>
GridSums GainsPass(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c,
                   float* below, float* gain) {
  const UnitInverses u = Inverses(r, c, kTwo);
  const float w = r.w, w0 = 1.0f - r.w, inv_a = u.a, inv_b = u.b, inv_ab = u.ab;
  // The rows and the constants held here, not read through r and c (the
  // stores to below and gain could alias them: each read again per step).
  const float* const rz[2] = {r.z[0], r.z[1]};
  const float rt[2] = {r.t[0], r.t[1]}, cap_c = c.cap, inv_dx = c.inv_dx;
  const auto row = [&](auto tag, int k, std::ptrdiff_t i) {
    using T = decltype(tag);
    const T a0 = At<T>(rz[k], i), a1 = At<T>(rz[k], i + 1);
    return std::pair{a0 + Broadcast<T>(rt[k]) * (a1 - a0), a1 - a0};
  };
  const auto one = [&](auto tag, std::ptrdiff_t i, Sums<decltype(tag)>& sums) {
    using T = decltype(tag);
    auto [z, rise] = row(tag, 0, i);
    T inv = Broadcast<T>(inv_a);
    if constexpr (kTwo) {
      const auto [zb, rise_b] = row(tag, 1, i);
      const auto a_known = z == z;
      const auto b_known = zb == zb;
      const auto both = a_known & b_known;
      z = both ? Broadcast<T>(w0) * z + Broadcast<T>(w) * zb : (b_known ? zb : z);
      rise = both ? Broadcast<T>(w0) * rise + Broadcast<T>(w) * rise_b : (b_known ? rise_b : rise);
      inv = both ? Broadcast<T>(inv_ab) : (b_known ? Broadcast<T>(inv_b) : inv);
    }
    const T zi = At<T>(zn, i), d = zi - z, zero = Broadcast<T>(0.0f);
    if constexpr (std::is_same_v<T, float>) {
      below[i] = z, gain[i] = d < zero ? zero : d;
    } else {
      vec::Store(below + i, z), vec::Store(gain + i, d < zero ? zero : d);
    }
    // Add's terms (kLocal), each over the variance by its inverse; the
    // slope is the rise / dx, its factors (2 / dx, 2 / dx^2) taken once at
    // the end.
    const T p = d * inv, chi = d * p, cap = Broadcast<T>(cap_c);
    const auto present = zi == zi, under = chi < cap;
    sums.first += present ? (under ? chi : cap) : zero;
    const auto fits = present & under;
    const T p_fits = fits ? p : zero, inv_fits = fits ? inv : zero;
    sums.second += p_fits * rise;
    sums.third += (rise * inv_fits) * rise;
  };
  Sums<V8> wide;
  std::ptrdiff_t i = begin;
  for (; i + 8 <= end; i += 8) one(V8{}, i, wide);
  Sums<float> narrow;
  for (; i < end; ++i) one(0.0f, i, narrow);
  GridSums total = Total(wide, narrow);
  total.second *= 2.0 * inv_dx, total.third *= 2.0 * inv_dx * static_cast<double>(inv_dx);
  return total;
}

GridSums Gains(const float* zn, const GridRows& r, std::ptrdiff_t begin, std::ptrdiff_t end, const GridShared& c,
               float* below, float* gain) {
  return r.count == 2 ? GainsPass<true>(zn, r, begin, end, c, below, gain)
                      : GainsPass<false>(zn, r, begin, end, c, below, gain);
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

// Settle's two rules for a flank of the layer below (part/registration.cc
// FlankPoints), eight points a register: where |z - under| <= tau, the
// rise to the next point beyond steep times the step (first), or not, but
// beyond run times it and again to the point after, the same way (second).
template <class T>
inline void AddFlank(T d, T first, T second, T step, T next, float tau, float steep, float run, Sums<T>& s) {
  const T zero = Broadcast<T>(0.0f), one = Broadcast<T>(1.0f);
  const T a = first < zero ? -first : first, b = second < zero ? -second : second;
  const auto agree = (d <= Broadcast<T>(tau)) & (d >= Broadcast<T>(-tau));
  const auto big = a > Broadcast<T>(steep) * step;
  s.first += (agree & big) ? one : zero;
  s.second += (agree & !big & (a > Broadcast<T>(run) * step) & (first * second > zero) & (b > Broadcast<T>(run) * next))
                  ? one
                  : zero;
}

GridSums Flanks(const float* x, const float* z, const float* under, std::size_t n, float tau, float steep, float run) {
  Sums<V8> wide;
  std::size_t i = 0;
  using vec::Load;
  for (; i + 10 <= n; i += 8) {
    const V8 u0 = Load(under + i), u1 = Load(under + i + 1), u2 = Load(under + i + 2);
    const V8 x0 = Load(x + i), x1 = Load(x + i + 1), x2 = Load(x + i + 2);
    AddFlank<V8>(Load(z + i) - u0, u1 - u0, u2 - u1, x1 - x0, x2 - x1, tau, steep, run, wide);
  }
  Sums<float> narrow;
  for (; i + 2 < n; ++i)
    AddFlank<float>(z[i] - under[i], under[i + 1] - under[i], under[i + 2] - under[i + 1], x[i + 1] - x[i],
                    x[i + 2] - x[i + 1], tau, steep, run, narrow);
  return Total(wide, narrow);
}

// core/median.h's order for NaN: std::min(a, b) is b < a ? b : a.
template <class T>
inline T StdMin(T a, T b) {
  return b < a ? b : a;
}
template <class T>
inline T StdMax(T a, T b) {
  return a < b ? b : a;
}
template <class T>
inline T StdMedian3(T a, T b, T c) {
  return StdMax(StdMin(a, b), StdMin(StdMax(a, b), c));
}

// Eight medians at a time, each lane keeping its greatest and where (the
// first, as the scalar loop's strict >); the lanes' greatest then, at its
// least index, and the rest on from there one at a time.
std::size_t Crest(const float* z, std::size_t lo, std::size_t hi) {
  const float none = -__builtin_inff();
  V8 top = vec::Splat(none), where = vec::Splat(0.0f);
  const V8 lanes{0, 1, 2, 3, 4, 5, 6, 7};
  std::size_t k = lo;
  for (; k + 8 <= hi; k += 8) {
    const V8 m = StdMedian3(vec::Load(z + k - 1), vec::Load(z + k), vec::Load(z + k + 1));
    const auto higher = m > top;
    top = higher ? m : top;
    where = higher ? vec::Splat(static_cast<float>(k - lo)) + lanes : where;
  }
  float best = none;
  std::size_t crest = lo;
  for (int i = 0; i < 8; ++i)
    if (top[i] > best || (top[i] == best && best > none && lo + static_cast<std::size_t>(where[i]) < crest))
      best = top[i], crest = lo + static_cast<std::size_t>(where[i]);
  for (; k < hi; ++k)
    if (const float m = StdMedian3(z[k - 1], z[k], z[k + 1]); m > best) best = m, crest = k;
  return crest;
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
                                 RowsAtPlaces,
                                 Flanks,
                                 Gains,
                                 Crest};

}  // namespace

const PartKernel& PartKernelBuild() { return kPartKernel; }

}  // namespace bead::part::BEAD_KERNEL
