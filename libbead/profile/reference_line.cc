#include "libbead/profile/reference_line.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "libbead/profile/kernel.h"
#include "libbead/core/median.h"
#include "libbead/profile/vec8.h"
#include "libbead/profile/vec_sort.h"

namespace bead {
namespace BEAD_KERNEL {
namespace {

// The MAD of a normal distribution times this is its standard deviation.
constexpr double kMadToSigma = 1.482602218505602;

// Ranks a group of V * 8 candidates (values[c, c + 8V)) against all n
// values at once: each lane counts the values below it and at or below it,
// and the lanes holding order statistic k1 or k2 keep their value.
template <int V>
void RankGroup(const float* values, std::size_t n, std::size_t c, int32_t k1, int32_t k2, vec::V8& pick1,
               vec::V8& pick2) {
  using namespace vec;
  V8 cand[V];
  M8 lt[V], le[V];
  for (int q = 0; q < V; ++q) cand[q] = Load(values + c + 8 * q), lt[q] = M8{}, le[q] = M8{};
  for (std::size_t j = 0; j < n; ++j) {
    const V8 v = Splat(values[j]);
    for (int q = 0; q < V; ++q) {
      lt[q] += v < cand[q];  // lanes are -1 where true
      le[q] += v <= cand[q];
    }
  }
  const V8 none = Splat(-std::numeric_limits<float>::infinity());
  for (int q = 0; q < V; ++q) {
    // Order statistic k sits where (values below) <= k < (values at or below).
    pick1 = Max(pick1, Select((lt[q] >= -k1) & (le[q] < -k1), cand[q], none));
    pick2 = Max(pick2, Select((lt[q] >= -k2) & (le[q] < -k2), cand[q], none));
  }
}

// The median of values[0, n), by counting for each value how many lie
// below it: no branch depends on the data, which on the few dozen samples
// here beats a selection. `values` must have room for n rounded up to a
// multiple of 8 (the padding is set to +infinity, which no rank reaches).
float CountingMedian(float* values, std::size_t n) {
  using namespace vec;
  const std::size_t padded = (n + 7) / 8 * 8;
  for (std::size_t i = n; i < padded; ++i) values[i] = std::numeric_limits<float>::infinity();
  // Order statistics k1 = (n - 1) / 2 and k2 = n / 2 (equal for odd n).
  const auto k1 = static_cast<int32_t>((n - 1) / 2), k2 = static_cast<int32_t>(n / 2);
  V8 pick1 = Splat(-std::numeric_limits<float>::infinity()), pick2 = pick1;
  std::size_t c = 0;
  for (; c + 32 <= padded; c += 32) RankGroup<4>(values, n, c, k1, k2, pick1, pick2);
  switch ((padded - c) / 8) {
    case 3:
      RankGroup<3>(values, n, c, k1, k2, pick1, pick2);
      break;
    case 2:
      RankGroup<2>(values, n, c, k1, k2, pick1, pick2);
      break;
    case 1:
      RankGroup<1>(values, n, c, k1, k2, pick1, pick2);
      break;
    default:
      break;
  }
  return 0.5f * (MaxOf(pick1) + MaxOf(pick2));
}

// An area's points: indices [begin, end) of the point set (x increasing),
// how many of them have a finite z (counted where needed: the usual path
// counts them while summing), and the spacing of the samples for the
// robust statistics (every stride-th point, dropouts skipped).
struct AreaRange {
  std::size_t begin = 0, end = 0, valid = 0, stride = 1;
  std::size_t size() const { return end - begin; }
  void Count(const PointSet& p) { valid = BEAD_KERNEL::CountFiniteZ(p, begin, end); }
};

AreaRange RangeOf(const PointSet& p, const ReferenceArea& area, int max_samples, std::size_t* hints) {
  AreaRange r;
  r.begin = LowerIndex(p, area.x_min_mm, hints[0]);
  r.end = std::max(r.begin, UpperIndex(p, area.x_max_mm, hints[1]));
  const std::size_t m = static_cast<std::size_t>(std::max(max_samples, 1));
  r.stride = r.size() <= m ? 1 : (r.size() + m - 1) / m;
  return r;
}

// An area's samples, x into xs and z into zs: the points stride/2,
// stride/2 + stride, ... with a finite z (packed without a branch); returns
// how many. Where the dropouts hit nearly every sampled point, every point.
std::size_t Samples(const PointSet& p, const AreaRange& r, float* xs, float* zs) {
  auto take = [&](std::size_t stride) {
    std::size_t count = 0;
    for (std::size_t i = r.begin + stride / 2; i < r.end; i += stride) {
      const float z = p.z[i];
      xs[count] = p.x[i];
      zs[count] = z;
      count += (z - z) == 0.0f;
    }
    return count;
  };
  const std::size_t count = take(r.stride);
  return count >= std::min<std::size_t>(r.valid, 3) ? count : take(1);
}

// The line in shifted coordinates: z - z0 = c + b (x - x0).
struct ShiftedLine {
  double x0 = 0, z0 = 0, c = 0, b = 0;
};

// Median of sorted values.
double SortedMedian(const float* xs, std::size_t n) {
  return n % 2 == 1 ? xs[n / 2] : 0.5 * (double(xs[n / 2 - 1]) + double(xs[n / 2]));
}

// The median of the medians of three (values i, i + g, i + 2g for
// g = n / 3; below 9 values, the plain median). A median of three is off
// only if two of its values are outliers, so any arrangement of fewer than
// a third of the values being outliers leaves it among the good ones, and
// random outliers at 20 % spoil it with probability below 1e-4 even for 16
// triples; with a third of the candidates the counting is cheap. The
// median of three draws has the median of their distribution, so this
// estimates the same median. `triples` has room for n / 3 + 8 values.
float MedianOfTriples(float* values, std::size_t n, float* triples) {
  if (n < 9) return CountingMedian(values, n);
  using namespace vec;
  const std::size_t g = n / 3;
  std::size_t i = 0;
  for (; i + 8 <= g; i += 8) {
    const V8 a = Load(values + i), b = Load(values + i + g), c = Load(values + i + 2 * g);
    Store(triples + i, vec::Median3(a, b, c));
  }
  for (; i < g; ++i) triples[i] = Median3(values[i], values[i + g], values[i + 2 * g]);
  return CountingMedian(triples, g);
}

// The centre of an area's samples (x increasing): the median of the
// medians of three of z, and the median x of the samples those medians
// stand for (i + g on a straight line).
void AreaCentre(const float* xs, float* zs, std::size_t count, float* triples, double& x_mid, double& z_mid) {
  z_mid = MedianOfTriples(zs, count, triples);
  x_mid = count < 9 ? SortedMedian(xs, count) : SortedMedian(xs + count / 3, count / 3);
}

// The start: a line through both areas' centres, and the robust spread of
// the samples' residuals about it (their MAD, as the median of medians of
// three: the median of three draws shares the median of their
// distribution).
struct Start {
  ShiftedLine line;
  double mad = 0.0;
  bool ok = false;
};

// From every stride-th point of each area (any size, any dropouts).
Start SampledStart(const PointSet& p, const AreaRange& rl, const AreaRange& rr, float* scratch) {
  // Scratch layout: the left and right samples' z (each padded to a
  // multiple of 8 for the median), then their x, then the residuals (room
  // for every point of the areas: Samples may take them all).
  const std::size_t room_l = (rl.size() + 16) / 8 * 8, room_r = (rr.size() + 16) / 8 * 8;
  float* zl_s = scratch;
  float* zr_s = zl_s + room_l;
  float* xl_s = zr_s + room_r;
  float* xr_s = xl_s + room_l;
  float* resid = xr_s + room_r;
  float* triples = resid + room_l + room_r;
  const std::size_t cl = Samples(p, rl, xl_s, zl_s), cr = Samples(p, rr, xr_s, zr_s);
  Start start;
  if (!(xr_s[0] > xl_s[cl - 1])) return start;  // overlapping areas
  double xl, zl, xr, zr;
  AreaCentre(xl_s, zl_s, cl, triples, xl, zl);
  AreaCentre(xr_s, zr_s, cr, triples, xr, zr);
  start.line = ShiftedLine{0.5 * (xl + xr), 0.5 * (zl + zr), 0.0, (zr - zl) / (xr - xl)};
  const auto x0 = static_cast<float>(start.line.x0), z0 = static_cast<float>(start.line.z0);
  const auto b0 = static_cast<float>(start.line.b);
  for (std::size_t k = 0; k < cl; ++k) resid[k] = std::abs((zl_s[k] - z0) - b0 * (xl_s[k] - x0));
  for (std::size_t k = 0; k < cr; ++k) resid[cl + k] = std::abs((zr_s[k] - z0) - b0 * (xr_s[k] - x0));
  start.mad = MedianOfTriples(resid, cl + cr, triples);
  start.ok = true;
  return start;
}

// The usual case, from 48 points per area without a loop over points: six
// spots of eight adjacent points spread evenly over each area, the triples
// formed across spots j, j + 2, j + 4 (so each triple spans the area, and a
// glint must cover two of its three spots to spoil it). A dropout takes its
// neighbour's value, or counts as an outlier (+infinity) where both are
// out; the MAD is taken over both areas' 32 triples (each area's 16 alone,
// with dropouts as outliers, failed once in 500 profiles with 20 % spikes
// and 5 % dropouts). Not ok when the dropouts are too many; then
// SampledStart, which skips them.
constexpr std::size_t kSpots = 6, kSpotSamples = 8 * kSpots;

Start SpotStart(const PointSet& p, const AreaRange& rl, const AreaRange& rr, float* scratch) {
  using namespace vec;
  const V8 inf = Splat(std::numeric_limits<float>::infinity());
  float* zs = scratch;  // [area][spot][8]
  float* xs = zs + 2 * kSpotSamples;
  float* triples = xs + 2 * kSpotSamples;  // 32
  double x_mid[2], z_mid[2];
  for (int a = 0; a < 2; ++a) {
    const AreaRange& r = a == 0 ? rl : rr;
    float* z = zs + a * kSpotSamples;
    float* x = xs + a * kSpotSamples;
    V8 x_sum{};  // float: the start's centre needs no more
    for (std::size_t j = 0; j < kSpots; ++j) {
      const std::size_t at = r.begin + (r.size() - 8) * j / (kSpots - 1);
      // A dropout takes its neighbour's value (pairs of lanes swapped), or
      // +infinity when both are out.
      const V8 spot = Load(p.z + at);
      const V8 pair = __builtin_shufflevector(spot, spot, 1, 0, 3, 2, 5, 4, 7, 6);
      const V8 filled = Select(spot == spot, spot, pair);
      Store(z + 8 * j, Select(filled == filled, filled, inf));
      const V8 spot_x = Load(p.x + at);
      Store(x + 8 * j, spot_x);
      x_sum += spot_x;
    }
    for (std::size_t t = 0; t < 2; ++t)
      Store(triples + 16 * a + 8 * t, vec::Median3(Load(z + 8 * t), Load(z + 8 * (t + 2)), Load(z + 8 * (t + 4))));
    x_mid[a] = Sum(x_sum) / kSpotSamples;
    z_mid[a] = vec::SortedMedian<2>(triples + 16 * a);
  }
  Start start;
  if (!(std::isfinite(z_mid[0]) && std::isfinite(z_mid[1]))) return start;
  start.line = ShiftedLine{0.5 * (x_mid[0] + x_mid[1]), 0.5 * (z_mid[0] + z_mid[1]), 0.0,
                           (z_mid[1] - z_mid[0]) / (x_mid[1] - x_mid[0])};
  const V8 x0 = Splat(static_cast<float>(start.line.x0)), z0 = Splat(static_cast<float>(start.line.z0));
  const V8 b0 = Splat(static_cast<float>(start.line.b));
  for (std::size_t k = 0; k < 2 * kSpotSamples; k += 8)
    Store(zs + k, Abs((Load(zs + k) - z0) - b0 * (Load(xs + k) - x0)));
  for (std::size_t a = 0; a < 2; ++a)
    for (std::size_t t = 0; t < 2; ++t) {
      const float* r = zs + a * kSpotSamples + 8 * t;
      Store(triples + 16 * a + 8 * t, vec::Median3(Load(r), Load(r + 16), Load(r + 32)));
    }
  start.mad = vec::SortedMedian<4>(triples);
  start.ok = std::isfinite(start.mad);
  return start;
}

// Least-squares sums over both areas' points within `band` (vertical) of
// the line, of dx = x - x0 and of their residual r about the line (a
// dropout's NaN residual is never within it), each area's count of them,
// and each area's count of points with a finite z. Fitting the residuals
// (a correction to the line) rather than z keeps the float sums at the
// scale of the noise: the sum of squares then does not cancel against the
// tilt's.
struct Sums {
  double n = 0, sx = 0, sr = 0, sxx = 0, sxr = 0, srr = 0;
  double n_left = 0, n_right = 0;
  std::size_t finite_left = 0, finite_right = 0;
};

Sums InlierSums(const PointSet& p, const AreaRange& left, const AreaRange& right, const ShiftedLine& line,
                double band) {
  using namespace vec;
  const float x0 = static_cast<float>(line.x0), z0 = static_cast<float>(line.z0);
  const float c = static_cast<float>(line.c), b = static_cast<float>(line.b), bw = static_cast<float>(band);
  const V8 vx0 = Splat(x0), vz0 = Splat(z0), vc = Splat(c), vb = Splat(b), vbw = Splat(bw);
  V8 sx{}, sr{}, sxx{}, sxr{}, srr{};
  Sums sums;
  auto add = [&](V8 x, V8 z, M8 lane_in, M8& n, M8& finite) {
    const V8 dx = x - vx0;
    const V8 res = (z - vz0) - vc - vb * dx;
    const M8 in = (Abs(res) <= vbw) & lane_in;
    const V8 idx = Select(in, dx, V8{}), ires = Select(in, res, V8{});
    finite += (z == z) & lane_in;  // lanes are -1 where true
    n += in;
    sx += idx;
    sr += ires;
    sxx += idx * idx;
    sxr += idx * ires;
    srr += ires * ires;
  };
  auto area = [&](const AreaRange& r, double& inliers, std::size_t& finite_count) {
    M8 n{}, finite{};
    std::size_t i = r.begin;
#pragma GCC unroll 2
    for (; i + 8 <= r.end; i += 8) add(Load(p.x + i), Load(p.z + i), ~M8{}, n, finite);
    if (i < r.end && r.size() >= 8) {
      // The last eight points, without the lanes already added.
      const std::size_t last = r.end - 8;
      add(Load(p.x + last), Load(p.z + last), LanesFrom(last, i), n, finite);
    } else {
      for (; i < r.end; ++i) {
        const float dx = p.x[i] - x0, res = (p.z[i] - z0) - c - b * dx;
        finite[0] -= p.z[i] == p.z[i];
        if (!(std::abs(res) <= bw)) continue;
        n[0] -= 1;
        sx[0] += dx, sr[0] += res, sxx[0] += dx * dx, sxr[0] += dx * res, srr[0] += res * res;
      }
    }
    inliers = -SumInt(n);
    finite_count = static_cast<std::size_t>(-SumInt(finite));
  };
  area(left, sums.n_left, sums.finite_left);
  area(right, sums.n_right, sums.finite_right);
  sums.n = sums.n_left + sums.n_right;
  sums.sx = Sum(sx), sums.sr = Sum(sr), sums.sxx = Sum(sxx), sums.sxr = Sum(sxr), sums.srr = Sum(srr);
  return sums;
}

}  // namespace

ReferenceLine FitReferenceLine(const PointSet& p, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& w) {
  ReferenceLine result;
  AreaRange rl = RangeOf(p, left, options.max_median_samples, w.area_hints);
  AreaRange rr = RangeOf(p, right, options.max_median_samples, w.area_hints + 2);
  const auto min_points = static_cast<std::size_t>(std::max(options.min_points_per_area, 1));
  // Each area's valid points, counted here (the spot start goes without).
  auto counted = [&] {
    rl.Count(p), rr.Count(p);
    result.points_available = static_cast<int>(rl.valid + rr.valid);
    return rl.valid >= min_points && rr.valid >= min_points;
  };
  if (rl.end > rr.begin) {  // overlapping areas
    counted();
    return result;
  }
  // Robust start: the line through each area's centre (median x, median
  // z of its samples), and the first band from the spread about it.
  const bool spots = options.max_median_samples >= static_cast<int>(kSpotSamples) && rl.size() >= kSpotSamples &&
                     rr.size() >= kSpotSamples;
  Start start;
  if (spots) start = SpotStart(p, rl, rr, w.scratch.data());
  if (!start.ok) {
    if (!counted()) return result;
    start = SampledStart(p, rl, rr, w.scratch.data());
  }
  if (!start.ok) return result;
  ShiftedLine line = start.line;
  const double floor_start = options.min_sigma_mm * std::sqrt(1.0 + line.b * line.b);
  double band = options.inlier_sigmas * std::max(kMadToSigma * start.mad, floor_start);

  // Least-squares refits on the inliers, each a correction (dc, db) fitted
  // to their residuals; each next band is the inliers' RMS about the new
  // line (the least-squares identity SSE = Srr - db Sxr on centred sums),
  // and the last refit's inliers and RMS are reported.
  const int refits = std::max(options.iterations, 1);
  for (int iter = 0; iter < refits; ++iter) {
    const Sums s = InlierSums(p, rl, rr, line, band);
    result.points_available = static_cast<int>(s.finite_left + s.finite_right);
    if (s.finite_left < min_points || s.finite_right < min_points) return result;
    if (s.n_left < options.min_points_per_area || s.n_right < options.min_points_per_area) return result;
    const double mx = s.sx / s.n, mr = s.sr / s.n;
    const double sxx = s.sxx - s.n * mx * mx;
    const double sxr = s.sxr - s.n * mx * mr;
    const double srr = s.srr - s.n * mr * mr;
    if (!(sxx > 0.0)) return result;
    const double db = sxr / sxx;
    line.b += db;
    line.c += mr - db * mx;
    const double rms_v = std::sqrt(std::max(srr - db * sxr, 0.0) / s.n);
    const double floor_v = options.min_sigma_mm * std::sqrt(1.0 + line.b * line.b);
    band = options.inlier_sigmas * std::max(rms_v, floor_v);
    if (iter + 1 == refits) {
      result.ok = true;
      result.slope = line.b;
      result.intercept_mm = line.z0 + line.c - line.b * line.x0;
      result.points_used = static_cast<int>(s.n);
      result.residual_rms_mm = rms_v / std::sqrt(1.0 + line.b * line.b);
    }
  }
  return result;
}

}  // namespace BEAD_KERNEL
}  // namespace bead
