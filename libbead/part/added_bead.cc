#include "libbead/part/added_bead.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "libbead/core/float_bits.h"
#include "libbead/core/median.h"
#include "libbead/part/grid_costs.h"
#include "libbead/part/part_kernel.h"
#include "libbead/part/registration.h"

namespace bead::part {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The points with a known gain (x and z: the profile's own where every
// point from the first with a surface below to the last has one, else
// those points copied out), and the gain there.
struct Gains {
  const float* x = nullptr;
  const float* z = nullptr;
  std::vector<double> d;
  std::vector<float> x_kept, z_kept;              // the copies, where needed
  double X(std::size_t k) const { return x[k]; }  // (in doubles: differences exact)
};

// grid: the new points on the surface below's grid (nullptr: not on it).
// The gains go to this thread's scratch (reused profile after profile).
const Gains& GainsAt(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double s,
                     const PointsOnGrid* grid) {
  thread_local std::vector<float> under;
  thread_local Gains g;
  if (grid) {
    grid->BelowAt(s, under);
    // The surface below known at every point from the first where it is
    // to the last (it ends beside the profile: the layer below is as
    // wide): each of those points its own gain.
    std::size_t a = 0, b = x.size();
    while (a < b && std::isnan(under[a])) ++a;
    while (b > a && std::isnan(under[b - 1])) --b;
    // The gains and whether any is unknown in one pass (by the bits:
    // core/float_bits.h); where one is, the copying path below writes
    // them again.
    g.d.resize(b - a);
    uint32_t unknown = 0;
    for (std::size_t i = a; i < b; ++i) {
      unknown |= static_cast<uint32_t>(IsNanBits(under[i]));
      g.d[i - a] = z[i] - static_cast<double>(under[i]);
    }
    if (!unknown) {
      g.x = x.data() + a, g.z = z.data() + a;
      return g;
    }
  }
  g.x_kept.resize(x.size()), g.z_kept.resize(x.size()), g.d.resize(x.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double b = grid ? under[i] : below.At(x[i] - s);
    g.x_kept[n] = x[i], g.z_kept[n] = z[i], g.d[n] = z[i] - b;
    n += !std::isnan(b);
  }
  g.d.resize(n);
  g.x = g.x_kept.data(), g.z = g.z_kept.data();
  return g;
}

// The median of v (reordered; NaN where empty).
double MedianOf(std::vector<float>& v) { return v.empty() ? kNaN : MiddleInPlace(v); }

// The same median, first looked for among the values near `guess` (the
// profile before's: a sensor's noise changes little from one profile to
// the next): where as many values lie below that band as put the median
// inside it, only the band is ordered.
double MedianNear(std::vector<float>& v, float guess) {
  thread_local std::vector<float> band;
  band.resize(v.size() + 8);
  std::size_t below = 0;
  const std::size_t in = ActivePartKernel().band(v.data(), v.size(), 0.85f * guess, 1.18f * guess, band.data(), below);
  const std::size_t k = v.size() / 2;
  if (!(guess > 0.0f) || k < below || k >= below + in) return MedianOf(v);
  return ActivePartKernel().kth(band.data(), in, k - below);
}

double NoiseOf(std::span<const float> z) {
  thread_local std::vector<float> second;
  thread_local float last_median = 0.0f;
  second.resize(z.size() > 2 ? z.size() - 2 : 0);
  if (!second.empty()) ActivePartKernel().second_differences(z.data(), z.size(), second.data());
  const double median = MedianNear(second, last_median);
  if (std::isfinite(median)) last_median = static_cast<float>(median);
  return std::max(0.002, 1.4826 * median / std::sqrt(6.0));
}

// The bead in a gain sequence: positions (into Gains) of its feet and of
// the bare points beyond them.
struct Span {
  std::size_t bare_left = 0, foot_left = 0, foot_right = 0, bare_right = 0;
};

// The run above `tau` with the largest integral; false when there is none
// of min_points points.
bool BestRun(const Gains& g, double tau, double max_gap, int min_points, Span& best) {
  double best_score = 0.0;
  const std::size_t n = g.d.size();
  const double* d = g.d.data();
  for (std::size_t i = 0; i < n;) {
    // (The bare points skipped four at a time: most of a profile.)
    while (i + 4 <= n && !((d[i] > tau) | (d[i + 1] > tau) | (d[i + 2] > tau) | (d[i + 3] > tau))) i += 4;
    if (i == n) break;
    if (!(d[i] > tau)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    double score = 0.0;
    while (j + 1 < n && d[j + 1] > tau && g.X(j + 1) - g.X(j) <= max_gap) {
      score += 0.5 * (d[j] + d[j + 1]) * (g.X(j + 1) - g.X(j));
      ++j;
    }
    if (static_cast<int>(j - i + 1) >= min_points && score > best_score) {
      best_score = score;
      best.foot_left = i;
      best.foot_right = j;
    }
    i = j + 1;
  }
  return best_score > 0.0;
}

// A foot is carried outward no further than where the gain rises again
// by more than this many noises (two points' gains differ by about two
// noises: each is a new point less the surface below's blend of points).
// (On a generator's wall seen at 0.1 mm whose fifth layer stood 0.34 mm
// inside the fourth's wall, the gain beside 38 of its 369 beads' ends rose
// 2.3-3.1 mm at one point, the fourth layer's wall interpolated across its
// cell, past a bare point 0.02-0.04 mm over the floor: the feet ran on to
// it, the area seen gained 0.3-0.4 mm^2 and the width two spacings.)
constexpr double kFootRiseNoises = 6.0;

// The feet carried out to the edge floor, where the gain does not rise
// outward by more than `rise`; false when a foot reaches the end of what is
// known or a long dropout.
bool Feet(const Gains& g, double floor, double rise, double max_gap, Span& s) {
  const auto carries = [&](std::size_t from, std::size_t to) {
    return g.d[to] > floor && g.d[to] <= g.d[from] + rise && std::abs(g.X(to) - g.X(from)) <= max_gap;
  };
  while (s.foot_left > 0 && carries(s.foot_left, s.foot_left - 1)) --s.foot_left;
  while (s.foot_right + 1 < g.d.size() && carries(s.foot_right, s.foot_right + 1)) ++s.foot_right;
  if (s.foot_left == 0 || s.foot_right + 1 >= g.d.size()) return false;
  s.bare_left = s.foot_left - 1;
  s.bare_right = s.foot_right + 1;
  return g.X(s.foot_left) - g.X(s.bare_left) <= max_gap && g.X(s.bare_right) - g.X(s.foot_right) <= max_gap;
}

// x where the gain crosses `level` between positions a and b.
double Crossing(const Gains& g, std::size_t a, std::size_t b, double level) {
  const double da = g.d[a], db = g.d[b];
  const double t = da == db ? 0.5 : std::clamp((level - da) / (db - da), 0.0, 1.0);
  return g.X(a) + t * (g.X(b) - g.X(a));
}

// The bead's centre: the vertex of the parabola through the new surface
// within `half` of its highest point (the top of the bead, whatever it
// overhangs; the gain's centroid leans toward an overhanging side). The
// highest point itself when the top is not curved downward there.
double CrestVertex(const Gains& g, const Span& s, std::size_t crest, double half) {
  const double xc = g.X(crest);
  double m[3][3] = {}, r[3] = {};
  int n = 0;
  for (std::size_t k = s.foot_left; k <= s.foot_right; ++k) {
    const double u = g.X(k) - xc;
    if (std::abs(u) > half) continue;
    const double f[3] = {1.0, u, u * u}, zk = g.z[k];
    for (int i = 0; i < 3; ++i) {
      r[i] += f[i] * zk;
      for (int j = 0; j < 3; ++j) m[i][j] += f[i] * f[j];
    }
    ++n;
  }
  if (n < 5) return xc;
  // Cramer's rule for the 3 x 3 normal equations.
  auto det = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const double d = det(m);
  if (d == 0.0) return xc;
  double c[3];
  for (int col = 0; col < 3; ++col) {
    double a[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a[i][j] = j == col ? r[i] : m[i][j];
    c[col] = det(a) / d;
  }
  if (!(c[2] < 0.0)) return xc;
  const double vertex = -c[1] / (2.0 * c[2]);
  return std::abs(vertex) <= half ? xc + vertex : xc;
}

// The crest: the first of the run's points whose median of three new
// heights (itself and its neighbours in the run, an end its own twice) is
// highest, as an offset from the left foot: floats, whose medians and
// order are their doubles'.
std::size_t CrestOf(const Gains& g, const Span& s) {
  const float* run = g.z + s.foot_left;
  const std::size_t n = s.foot_right - s.foot_left + 1;
  std::size_t crest = 0;
  float top = Median3(run[0], run[0], run[n > 1 ? 1 : 0]);
  for (std::size_t k = 1; k + 1 < n; ++k)
    if (const float m = Median3(run[k - 1], run[k], run[k + 1]); m > top) top = m, crest = k;
  if (n > 1 && Median3(run[n - 2], run[n - 1], run[n - 1]) > top) crest = n - 1;
  return crest;
}

// The bead's centre: the middle of its top, between the places either side
// of the crest where the new surface falls below the crest's height by half
// the lesser of its two drops (the crest's height less each foot's), each
// linear between the two points around it. A symmetric top's middle,
// rounded or flat: a tamped bead's flat top gives the parabola about its
// highest point no vertex (its highest point lies anywhere on the flat, and
// a generator's tamped walls' centres came out 1.1 mm off their beads'
// (median; 4.4 mm at four times the size), their walls' wander with them,
// where pressed ellipses' were 0.016 mm off). Where the lesser drop is
// under kTopDropNoises noises (a top hardly above its feet), the parabola's
// vertex (CrestVertex).
constexpr double kTopDropNoises = 6.0;
double TopMiddle(const Gains& g, const Span& s, std::size_t crest, double noise, double half) {
  const double top =
      Median3(g.z[crest > s.foot_left ? crest - 1 : crest], g.z[crest], g.z[std::min(crest + 1, s.foot_right)]);
  const double drop = std::min(top - g.z[s.foot_left], top - g.z[s.foot_right]);
  if (!(drop > kTopDropNoises * noise)) return CrestVertex(g, s, crest, half);
  // Each foot stands below the level (by half its drop at least): both
  // walks stop inside the run.
  const double level = top - 0.5 * drop;
  std::size_t l = crest, r = crest;
  while (l > s.foot_left && g.z[l - 1] >= level) --l;
  while (r < s.foot_right && g.z[r + 1] >= level) ++r;
  if (l == s.foot_left || r == s.foot_right) return CrestVertex(g, s, crest, half);
  const auto at = [&](std::size_t below, std::size_t above) {
    const double t = (level - g.z[below]) / (static_cast<double>(g.z[above]) - g.z[below]);
    return g.X(below) + t * (g.X(above) - g.X(below));
  };
  return 0.5 * (at(l - 1, l) + at(r + 1, r));
}

void Geometry(const Gains& g, const Span& s, double floor, AddedBead& out) {
  // Each bare point's gain at most the floor: where a foot stopped at a
  // rise, the point beyond is not the bead's (no change where it stopped
  // at the floor).
  const auto gain = [&](std::size_t k) {
    const double d = std::max(g.d[k], 0.0);
    return k == s.bare_left || k == s.bare_right ? std::min(d, floor) : d;
  };
  double area = 0.0;
  for (std::size_t k = s.bare_left; k < s.bare_right; ++k) {
    const double a = gain(k), b = gain(k + 1), dx = g.X(k + 1) - g.X(k);
    area += 0.5 * (a + b) * dx;
  }
  out.area_mm2 = area;
  out.width_mm = Crossing(g, s.foot_right, s.bare_right, floor) - Crossing(g, s.bare_left, s.foot_left, floor);
  out.edge_left_mm = g.d[s.foot_left], out.edge_right_mm = g.d[s.foot_right];
  const std::size_t crest = s.foot_left + CrestOf(g, s);
  const std::size_t lo = crest > s.foot_left ? crest - 1 : crest, hi = std::min(crest + 1, s.foot_right);
  out.height_mm = Median3(g.d[lo], g.d[crest], g.d[hi]);
  out.center_x_mm = TopMiddle(g, s, crest, out.noise_mm, 0.2 * out.width_mm);
}

// Where more than half the steps lie within a thousandth of one step's
// length (a sensor's uniform points, a few missing), the median is among
// them: their mean (tried from the first step and the middle one; NaN
// where neither is so common). Counted in one pass without branches;
// where every step is among them, their sum is the span.
double CommonStep(std::span<const float> x) {
  const std::size_t steps = x.size() - 1;
  for (std::size_t at : {std::size_t{0}, steps / 2}) {
    const float step = x[at + 1] - x[at], band = 1e-3f * step;
    const auto in = [&](std::size_t i) { return std::abs((x[i + 1] - x[i]) - step) <= band; };
    std::size_t count = 0;
    for (std::size_t i = 0; i < steps; ++i) count += in(i);
    if (!(2 * count > steps && step > 0.0f)) continue;
    if (count == steps) return (static_cast<double>(x.back()) - x.front()) / static_cast<double>(steps);
    double sum = 0.0;
    for (std::size_t i = 0; i < steps; ++i) sum += in(i) ? x[i + 1] - x[i] : 0.0f;
    return sum / static_cast<double>(count);
  }
  return kNaN;
}

// Whether the new surface lies under the old by tau over more points than
// stand over it by tau, and over kUnderShare of them (AddedStatus::
// kUnderSurfaceBelow); `under` then the median gain of those under. A
// correct pair of scans leaves under tau only the noise's tails (tau is six
// noises at least) and the few points of a steep wall the shift misses by a
// hair; a bead stands over it wherever one was laid.
bool UnderSurfaceBelow(const std::vector<double>& d, double tau, double& under) {
  // First every kUnderStride-th point: where under half the share lies
  // under among them, the whole cannot hold it but by a freak of sampling
  // (a correct pair of scans has none there; a wrong frame, most). (Every
  // point, counted first, took a tenth of the naive part profile's time.)
  constexpr std::size_t kUnderStride = 8;
  std::size_t sampled = 0, sampled_below = 0;
  for (std::size_t j = 0; j < d.size(); j += kUnderStride) ++sampled, sampled_below += d[j] < -tau;
  if (static_cast<double>(sampled_below) <= 0.5 * kUnderShare * static_cast<double>(sampled)) return false;
  std::size_t below = 0, above = 0;
  for (const double v : d) {
    below += v < -tau;
    above += v > tau;
  }
  if (below <= above || static_cast<double>(below) <= kUnderShare * static_cast<double>(d.size())) return false;
  std::vector<double> sunk;
  for (const double v : d)
    if (v < -tau) sunk.push_back(v);
  under = MiddleInPlace(sunk);
  return true;
}

}  // namespace

double ProfileNoiseMm(std::span<const float> z) { return NoiseOf(z); }

double PointSpacingMm(std::span<const float> x) {
  if (x.size() < 2) return 0.05;
  if (const double common = CommonStep(x); std::isfinite(common)) return std::max(common, 1e-4);
  thread_local std::vector<float> d;
  d.clear();
  for (std::size_t i = 1; i < x.size(); ++i) d.push_back(x[i] - x[i - 1]);
  return d.empty() ? 0.05 : std::max(MedianOf(d), 1e-4);
}

const char* AddedStatusName(AddedStatus s) {
  switch (s) {
    case AddedStatus::kValid:
      return "valid";
    case AddedStatus::kTooFewPoints:
      return "too_few_points";
    case AddedStatus::kNoSurfaceBelow:
      return "no_surface_below";
    case AddedStatus::kNoBead:
      return "no_bead";
    case AddedStatus::kBeadEdgeNotSeen:
      return "bead_edge_not_seen";
    case AddedStatus::kBeadInReferenceArea:
      return "bead_in_reference_area";
    case AddedStatus::kReferenceNotALine:
      return "reference_not_a_line";
    case AddedStatus::kUnderSurfaceBelow:
      return "under_surface_below";
    case AddedStatus::kBedMoved:
      return "bed_moved";
  }
  return "unknown";
}

AddedBead MeasureAddedBead(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                           bool register_shift, const AddedBeadOptions& o, const double* start_shift, double spacing_mm,
                           double start_hidden_sigma, double noise_mm, bool search_wide) {
  AddedBead out;
  out.noise_mm = std::isfinite(noise_mm) ? noise_mm : NoiseOf(z);
  const double tau = o.Threshold(out.noise_mm);
  const double floor = std::max(o.min_edge_floor_mm, o.edge_floor_sigmas * out.noise_mm);
  Registration reg;
  // The new points on the surface below's grid, where they lie on it
  // (part/grid_costs.h): the gains and the registration's costs eight
  // points at a time.
  thread_local PointsOnGrid on_grid;
  const PointsOnGrid* grid = on_grid.Make(x, z, below) ? &on_grid : nullptr;
  // Registered first, the gains taken once at the shift found (a profile
  // whose bead does not show is registered for nothing; checking it at
  // shift 0 first cost every profile a second pass over its gains).
  if (x.size() < 10) return out;  // kTooFewPoints: fewer gains still
  if (register_shift) {
    const double spacing = std::isfinite(spacing_mm) ? spacing_mm : PointSpacingMm(x);
    reg = Register(x, z, below, {tau, out.noise_mm, spacing}, o, start_shift, grid, start_hidden_sigma, search_wide);
  }
  const Gains& g = GainsAt(x, z, below, reg.shift, grid);
  if (g.d.size() < 10) return out;  // kTooFewPoints
  if (UnderSurfaceBelow(g.d, tau, out.under_mm)) {
    out.status = AddedStatus::kUnderSurfaceBelow;
    out.shift_mm = reg.shift;
    return out;
  }
  Span s;
  if (!BestRun(g, tau, o.max_gap_mm, o.min_bead_points, s)) {
    out.status = AddedStatus::kNoBead;
    return out;
  }
  const bool seen = Feet(g, floor, kFootRiseNoises * out.noise_mm, o.max_gap_mm, s);
  out.status = seen ? AddedStatus::kValid : AddedStatus::kBeadEdgeNotSeen;
  if (seen) Geometry(g, s, floor, out);
  out.shift_mm = reg.shift;
  out.shift_sigma_mm = reg.sigma;
  out.shift_hidden_sigma_mm = reg.hidden_sigma;
  out.shift_constrained = reg.constrained;
  out.registration_rms_mm = reg.rms;
  out.outside_points = reg.points;
  return out;
}

}  // namespace bead::part
