// The pieces of MeasureBead (bead_geometry.cc) that work on a profile's
// heights: computing them about the line, the spikes, the largest run above
// the threshold, the trapezoids and the sub-sample edge model. Internal to
// the kernel: included by bead_geometry.cc alone, once per instruction set
// (kernel.h), so that every piece inlines into MeasureBead; not installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "libbead/core/median.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/kernel.h"
#include "libbead/profile/vec8.h"

namespace bead {
namespace BEAD_KERNEL {
namespace {

// How far into each reference area the bead's search reaches, in points.
constexpr std::size_t kAreaMargin = 16;

// The points' heights h and along-line positions s about the line, for
// the points [begin, end) of the set with finite z only (begin a multiple
// of eight; w.kept_before records how many came before each group of eight
// points from begin, to find them again: SetIndex). In float and shifted: s
// is measured from `s_offset_mm` (double), so the rounding stays at the
// scale of the profile's width.
struct Heights {
  float* h = nullptr;
  float* s = nullptr;
  std::size_t n = 0;
  double s_offset_mm = 0.0;
  double inv_norm = 1.0;  // 1 / sqrt(1 + slope^2): along-line s to x
};

// Every group of eight points goes the same way, the finite ones packed to
// the front by one permutation: no branch depends on where the dropouts
// are (a test per block of them cost more in mispredictions than packing
// every group costs in instructions).
Heights ComputeHeights(const PointSet& p, std::size_t begin, std::size_t end, const ReferenceLine& line,
                       ProfileWorkspace& w) {
  using namespace vec;
  const double b = line.slope;
  const double inv_norm = 1.0 / std::sqrt(1.0 + b * b);
  const float x0 = p.x[(begin + end) / 2];
  const double z0 = line.intercept_mm + b * x0;  // the line at x0
  const float z0f = static_cast<float>(z0);
  const float dz0 = static_cast<float>(z0 - z0f);
  const float bf = static_cast<float>(b), inv = static_cast<float>(inv_norm);
  const V8 vx0 = Splat(x0), vz0 = Splat(z0f), vdz0 = Splat(dz0), vb = Splat(bf), vinv = Splat(inv);
  // Local pointers: the stores (memcpy) could alias the structs holding them.
  const float* px = p.x;
  const float* pz = p.z;
  float* hs = w.h.data();
  float* ss = w.s.data();
  int32_t* kept_before = w.kept_before.data();
  w.heights_begin = begin;
  w.heights_end = end;
  std::size_t m = 0, k = begin;
  for (; k + 8 <= end; k += 8) {
    *kept_before++ = static_cast<int32_t>(m);
    const V8 x = Load(px + k), z = Load(pz + k);
    const int bits = Bits((z - z) == 0.0f);
    const V8 dx = x - vx0, dz = z - vz0 - vdz0;
    const M8 keep = PackIndex(bits);
    Store(hs + m, Pack((dz - vb * dx) * vinv, keep));
    Store(ss + m, Pack((dx + vb * dz) * vinv, keep));
    m += static_cast<std::size_t>(__builtin_popcount(bits));
  }
  *kept_before = static_cast<int32_t>(m);  // before the last, partial group (if any)
  for (; k < end; ++k) {
    const float x = px[k], z = pz[k];
    if (!((z - z) == 0.0f)) continue;
    const float dx = x - x0, dz = z - z0f - dz0;
    hs[m] = (dz - bf * dx) * inv;
    ss[m++] = (dx + bf * dz) * inv;
  }
  kept_before[(end - begin) % 8 != 0 ? 1 : 0] = static_cast<int32_t>(m);  // after it
  // A point at (x, z) lies at s = (x + b (z - a)) / sqrt(1 + b^2) along
  // the line; at x0 on the line that is x0 sqrt(1 + b^2).
  return Heights{hs, ss, m, x0 * std::sqrt(1.0 + b * b), inv_norm};
}

// Index in the point set of the k-th height: in the group of eight at or
// after k / 8 (each holds at most eight) before the first with more than k
// heights before it, the (k - heights before)-th point with finite z.
std::size_t SetIndex(const PointSet& p, const ProfileWorkspace& w, std::size_t k) {
  using namespace vec;
  const std::size_t groups = (w.heights_end - w.heights_begin + 7) / 8;
  std::size_t g = k / 8;
  while (g + 1 < groups && static_cast<std::size_t>(w.kept_before[g + 1]) <= k) ++g;
  const std::size_t at = w.heights_begin + 8 * g;
  unsigned bits = 0;
  if (at + 8 <= p.n) {
    const V8 z = Load(p.z + at);
    bits = static_cast<unsigned>(Bits((z - z) == 0.0f));
  } else {
    for (std::size_t i = at; i < p.n; ++i) bits |= static_cast<unsigned>((p.z[i] - p.z[i]) == 0.0f) << (i - at);
  }
  for (std::size_t j = k - static_cast<std::size_t>(w.kept_before[g]); j > 0; --j) bits &= bits - 1;
  return at + static_cast<std::size_t>(__builtin_ctz(bits));
}

// The reference areas' points in the set: [left_begin, left_end) and
// [right_begin, right_end), x increasing.
struct AreaIndices {
  std::size_t left_begin, left_end, right_begin, right_end;
  bool InLeft(std::size_t i) const { return i >= left_begin && i < left_end; }
  bool InRight(std::size_t i) const { return i >= right_begin && i < right_end; }
};

// Spikes: points standing more than spike_mm off the median of themselves
// and their four nearest neighbours (median of five, so two adjacent
// spikes are caught too; three at the ends; never the first or last
// point). Only next to a jump of more than spike_mm: otherwise three of
// the five (the point and both neighbours) lie within spike_mm of the
// point, so their median does too. So blocks of 32 points are tested for
// jumps first, and only a block next to one is tested point by point,
// eight at a time. Writes their indices, increasing, to w.spikes; returns
// how many.
std::size_t FindSpikes(const Heights& g, float spike_mm, ProfileWorkspace& w) {
  using namespace vec;
  const float* h = g.h;
  const std::size_t n = g.n;
  if (n < 3) return 0;
  std::size_t count = 0;
  auto jump = [&](std::size_t k) { return std::abs(h[k + 1] - h[k]) > spike_mm; };  // between k and k + 1
  auto test = [&](std::size_t k) {                                                  // one point, 1 <= k <= n - 2
    const float med = (k >= 2 && k + 2 < n) ? Median5(h[k - 2], h[k - 1], h[k + 1], h[k + 2], h[k])
                                            : Median3(h[k - 1], h[k], h[k + 1]);
    if (std::abs(h[k] - med) > spike_mm) w.spikes[count++] = static_cast<int32_t>(k);
  };
  const V8 sp = Splat(spike_mm);
  // Points start .. start + 31 (start >= 2, start + 34 <= n), those before
  // `from` excepted (already tested), when a pair (k, k + 1) among them or
  // the pair before them jumps.
  auto block = [&](std::size_t start, std::size_t from, bool jump_before) {
    M8 jumps{};
    for (std::size_t i = start; i < start + 32; i += 8) jumps |= Abs(Load(h + i + 1) - Load(h + i)) > sp;
    if (!(jump_before || Any(jumps))) return;
    for (std::size_t i = start; i < start + 32; i += 8) {
      const V8 a = Load(h + i - 2), b = Load(h + i - 1), c = Load(h + i), d = Load(h + i + 1), e = Load(h + i + 2);
      const V8 lo = Max(Min(a, b), Min(d, e)), hi = Min(Max(a, b), Max(d, e));
      int bits = Bits((Abs(c - vec::Median3(lo, hi, c)) > sp) & LanesFrom(i, std::max(from, i)));
      for (; bits != 0; bits &= bits - 1) w.spikes[count++] = static_cast<int32_t>(i + __builtin_ctz(bits));
    }
  };
  // Point 1 alone (its median is of three); blocks of 32 from point 2, the
  // last one ending at point n - 3 (overlapping the one before); point n - 2
  // alone (its median is of three).
  if (jump(0) || jump(1)) test(1);
  std::size_t k = 2;
  for (; k + 34 <= n; k += 32) block(k, k, jump(k - 1));
  if (k + 2 < n && n >= 36) {
    block(n - 34, k, jump(n - 35));
    k = n - 2;
  }
  for (; k + 1 < n; ++k)
    if (jump(k - 1) || jump(k)) test(k);
  return count;
}

// Puts each run of adjacent spikes on the chord between the points either
// side of it (FindSpikes never marks the first or last point), in h and s
// alike. The trapezoids then add up to exactly what they would with the
// spikes left out, and no array is moved.
void BridgeSpikes(Heights& g, std::size_t spikes, const ProfileWorkspace& w) {
  for (std::size_t r = 0; r < spikes;) {
    const auto first = static_cast<std::size_t>(w.spikes[r]);
    std::size_t last = first;
    while (++r < spikes && static_cast<std::size_t>(w.spikes[r]) == last + 1) ++last;
    const std::size_t a = first - 1, b = last + 1;
    const float span = static_cast<float>(b - a);
    for (std::size_t k = first; k <= last; ++k) {
      const float t = static_cast<float>(k - a) / span;
      g.h[k] = g.h[a] + t * (g.h[b] - g.h[a]);
      g.s[k] = g.s[a] + t * (g.s[b] - g.s[a]);
    }
  }
}

// How many spikes lie in [first, last].
std::size_t SpikesWithin(const ProfileWorkspace& w, std::size_t first, std::size_t last) {
  std::size_t count = 0;
  for (std::size_t r = 0; r < w.n_spikes; ++r) {
    const auto k = static_cast<std::size_t>(w.spikes[r]);
    count += (k >= first) & (k <= last);
  }
  return count;
}

// Twice the trapezoid between points k and k + 1, eight at once.
vec::V8 TwoTrapezoids(const float* h, const float* s, std::size_t k) {
  using namespace vec;
  return (Load(h + k) + Load(h + k + 1)) * (Load(s + k + 1) - Load(s + k));
}

float Trapezoid(const Heights& g, std::size_t first, std::size_t last) {
  using namespace vec;
  V8 acc{};
  std::size_t k = first;
  for (; k + 8 <= last; k += 8) acc += TwoTrapezoids(g.h, g.s, k);
  if (k < last && last - first >= 8) {
    acc += Select(vec::LanesFrom(last - 8, k), TwoTrapezoids(g.h, g.s, last - 8), V8{});
    k = last;
  }
  float sum = Sum(acc);
  for (; k < last; ++k) sum += (g.h[k] + g.h[k + 1]) * (g.s[k + 1] - g.s[k]);
  return 0.5f * sum;
}

struct Run {
  std::size_t first = 0, last = 0;          // heights, inclusive
  std::size_t set_first = 0, set_last = 0;  // the same points' indices in the set
  bool found = false;
};

// A run of heights, as the indices in the set of its first and last
// point: every point with finite z between them is in it. Whether one of
// them lies in the area [begin, end) of the set.
bool TouchesArea(const PointSet& p, std::size_t first, std::size_t last, std::size_t begin, std::size_t end) {
  const std::size_t from = std::max(first, begin), to = std::min(last + 1, end);
  return from < to && BEAD_KERNEL::CountFiniteZ(p, from, to) > 0;
}

// Whether one of them lies outside both areas: one of its ends does, or it
// spans the gap between the areas and a point there has a finite z.
bool HasPointOutside(const PointSet& p, std::size_t first, std::size_t last, const AreaIndices& a) {
  const bool first_in = a.InLeft(first) || a.InRight(first), last_in = a.InLeft(last) || a.InRight(last);
  if (!first_in || !last_in) return true;
  if (a.InLeft(first) == a.InLeft(last)) return false;  // both in one area
  return BEAD_KERNEL::CountFiniteZ(p, a.left_end, a.right_begin) > 0;
}

// The run of consecutive points above `threshold` (gaps up to max_gap) with
// the largest integral, among runs holding a point outside both areas.
Run LargestRun(const PointSet& p, const Heights& g, float threshold, float max_gap, const AreaIndices& areas,
               const ProfileWorkspace& w) {
  const float* h = g.h;
  const float* s = g.s;
  const std::size_t n = g.n;
  const vec::V8 vt = vec::Splat(threshold), vg = vec::Splat(max_gap);
  using vec::Bits, vec::Load;
  // Thirty-two points at once, as bits: above the threshold; and above it
  // and within max_gap of the point before.
  auto above = [&](std::size_t k) {
    return static_cast<uint32_t>(Bits(Load(h + k) > vt) | Bits(Load(h + k + 8) > vt) << 8 |
                                 Bits(Load(h + k + 16) > vt) << 16 | Bits(Load(h + k + 24) > vt) << 24);
  };
  auto continues = [&](std::size_t j) {
    uint32_t bits = 0;
    for (int q = 0; q < 4; ++q) {
      const std::size_t i = j + 8 * static_cast<std::size_t>(q);
      bits |= static_cast<uint32_t>(Bits((Load(h + i) > vt) & (Load(s + i) - Load(s + i - 1) <= vg))) << (8 * q);
    }
    return bits;
  };
  // The first point from k on above the threshold (n if none), and the
  // first from j on that does not continue a run: found from the bits, the
  // last, partial 32 as the 32 ending at the profile's end, the bits of
  // points already passed shifted out (single points only in a profile of
  // fewer than 33).
  auto first_bit = [](std::size_t at, uint32_t bits) { return at + static_cast<std::size_t>(__builtin_ctz(bits)); };
  auto next_above = [&](std::size_t k) {
    for (; k + 32 <= n; k += 32)
      if (const uint32_t bits = above(k)) return first_bit(k, bits);
    if (k < n && n >= 33) {
      const uint32_t bits = above(n - 32) >> (k - (n - 32));
      return bits != 0 ? first_bit(k, bits) : n;
    }
    while (k < n && !(h[k] > threshold)) ++k;
    return k;
  };
  auto run_end = [&](std::size_t j) {
    for (; j + 32 <= n; j += 32)
      if (const uint32_t ends = ~continues(j)) return first_bit(j, ends);
    if (j < n && n >= 33) {
      const uint32_t ends = ~continues(n - 32) >> (j - (n - 32));
      return ends != 0 ? first_bit(j, ends) : n;
    }
    while (j < n && h[j] > threshold && s[j] - s[j - 1] <= max_gap) ++j;
    return j;
  };
  // The integrals are summed only when two runs compete (the usual
  // profile has one); negative: not summed yet.
  Run best;
  float best_integral = -1.0f;
  for (std::size_t k = next_above(0); k < n;) {
    const std::size_t j = run_end(k + 1);
    const std::size_t set_first = SetIndex(p, w, k), set_last = SetIndex(p, w, j - 1);
    if (HasPointOutside(p, set_first, set_last, areas)) {
      const Run run{k, j - 1, set_first, set_last, true};
      if (!best.found) {
        best = run;
      } else {
        if (best_integral < 0.0f) best_integral = Trapezoid(g, best.first, best.last);
        const float integral = Trapezoid(g, run.first, run.last);
        if (integral > best_integral) best = run, best_integral = integral;
      }
    }
    k = next_above(j);
  }
  return best;
}

// The bead's edge between its last bare sample and its first bead sample,
// the sub-sample model of bead_geometry.h. x2 and x3 are the distances
// of the second and third bead samples inward from the first (heights h1,
// h2, h3), gap that of the bare sample outward; trap the trapezoid the
// plain integral gives the gap; floor the height noise floor. Returns the
// piece that replaces the trapezoid, the edge's distance outward from the
// first bead sample, and the piece's centroid's distance outward from it.
struct EdgePiece {
  double area = 0.0, reach = 0.0, centroid = 0.0;
};
EdgePiece EdgeModel(double gap, double trap, double h1, double x2, double h2, double x3, double h3, double floor) {
  EdgePiece e;
  if (!(gap > 0.0) || !(h1 > 0.0)) return e;
  // A wall the trapezoid integrates exactly in the mean: a step anywhere in
  // the gap gives on average the trapezoid's area, the area of a step at
  // the gap's middle (when the bare sample reads 0).
  e.area = trap;
  e.reach = std::min(trap / h1, gap);
  e.centroid = 0.5 * e.reach;
  // The parabola through the first three bead samples, q(x) = a x^2 + b x
  // + h1 with x inward from the first; below it, outward (x = -u), it
  // meets the surface at its smallest positive root (the continuation of
  // h1 / b as a -> 0).
  if (!(x2 > 0.0) || !(x3 > x2)) return e;
  const double r2 = (h2 - h1) / x2, r3 = (h3 - h1) / x3;
  const double a = (r2 - r3) / (x2 - x3), b = r2 - a * x2;  // b: the wall's slope at the first sample
  const double disc = b * b - 4.0 * a * h1;
  if (!(b > 0.0) || !(disc >= 0.0)) return e;  // level or rising outward: a wall in the gap
  double u = 2.0 * h1 / (b + std::sqrt(disc));
  // The bare sample reads within the noise floor of the surface: a root
  // that far beyond it (floor / slope) still meets the surface at it.
  if (!(u <= gap + floor / b)) return e;  // the curve does not reach the surface in the gap: a wall in the gap
  u = std::min(u, gap);
  // A sloped wall meeting the surface inside the gap: the parabola's piece
  // down to it. The trapezoids inward cut the chords of a curved top and
  // the corner above a straight wall; the end term (x2^2 / 12) f'(a) of
  // the Euler-Maclaurin formula (Abramowitz and Stegun 23.1.30, its first
  // correction term) gives them back on average.
  const double u2 = u * u;
  e.reach = u;
  e.area = a * u2 * u / 3.0 - b * u2 / 2.0 + h1 * u;
  e.centroid = e.area > 0.0 ? (a * u2 * u2 / 4.0 - b * u2 * u / 3.0 + h1 * u2 / 2.0) / e.area : u / 3.0;
  e.area += x2 * x2 / 12.0 * b;
  return e;
}

}  // namespace
}  // namespace BEAD_KERNEL
}  // namespace bead
