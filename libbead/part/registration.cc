#include "libbead/part/registration.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "libbead/part/grid_costs.h"

namespace bead::part {
namespace {

// The truncated squared gain over every point, in noise variances (the
// new point's and the surface below's there): a point where the surfaces
// agree counts its squared gain, one inside the new bead (or off the
// surface below) the threshold's square, whatever the shift. Least where
// the most points agree.
double TruncatedCost(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double s,
                     const RegistrationScale& k, double margin, const PointsOnGrid* grid) {
  const double noise2 = k.noise * k.noise, cap = k.Cap();
  const double lo = below.first_mm() + margin, hi = below.last_mm() - margin;
  if (grid) return grid->TruncatedCost(s, noise2, cap, lo, hi);
  double sum = 0.0;
  // The surface below's variance is at most one point's (surface_below.h):
  // a gain beyond cap at twice the noise variance is capped whatever it is.
  const double capped_beyond = 2.0 * cap * noise2;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] < lo || x[i] > hi) continue;
    const SurfaceGrid::Sample b = below.SampleAt(x[i] - s);
    const double d = z[i] - b.z;
    if (std::isnan(d) || d * d >= capped_beyond) {
      sum += cap;
      continue;
    }
    sum += std::min(d * d / (noise2 * (1.0 + b.variance)), cap);
  }
  return sum;
}

// The cost on a grid of shifts at a quarter of the point spacing (a lone
// wall of the layer below moves one point in or out of agreement per
// spacing).
struct CostCurve {
  std::vector<double> s, cost;
};

CostCurve Scan(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double centre, double half,
               const RegistrationScale& k, const PointsOnGrid* grid) {
  const double step = std::max(0.25 * k.spacing, 1e-3);
  CostCurve c;
  for (double s = centre - half; s <= centre + half + 1e-12; s += step) {
    c.s.push_back(s);
    c.cost.push_back(TruncatedCost(x, z, below, s, k, half + std::abs(centre), grid));
  }
  return c;
}

// The cost averaged over one point spacing (`half` either side): a wall of
// the layer below moves a point in or out of agreement per spacing of
// shift, a step the average turns into a slope.
std::vector<double> Smoothed(const CostCurve& c, std::size_t half) {
  std::vector<double> out(c.cost.size());
  for (std::size_t k = 0; k < c.cost.size(); ++k) {
    const std::size_t lo = k >= half ? k - half : 0, hi = std::min(k + half, c.cost.size() - 1);
    double sum = 0.0;
    for (std::size_t j = lo; j <= hi; ++j) sum += c.cost[j];
    out[k] = sum / static_cast<double>(hi - lo + 1);
  }
  return out;
}

// The gain's RMS where the surfaces agree at the shift found, how many
// points agree, and whether the shift is constrained: only where the layer
// below shows beside the new bead (a flank it does not cover: points that
// agree where the surface below slopes) is there anything to register on;
// a cost that rises because a shifted old bead would stick out from under
// the new one says where the old bead could lie hidden, not where it lies.
// A point of that flank is one that agrees where the surface below rises
// (or falls) over the spacing to the next point by more than
// kFeatureSigmas of what a flat surface's noise rises by (two points'
// difference: sqrt 2 noises; 6.8e-6 of a bare bed's points by chance), or
// by over three noises there and again over the next spacing, the same way
// (RunFeatures: a flank is a run; 1.6e-6 of a bare bed's points by
// chance). (Counted wherever it rose by three noises once, 3.4 % of a bare
// bed's points: a bed's 600 held 5-19 such points, and a generator's tamped
// bead covering the one below, nothing of it showing, was tracked as
// constrained at 0.014 mm, 0.09 mm off, its layer's areas 0.8 % high at a
// third of its sigmas' coverage.)
constexpr double kFeatureSigmas = 4.5, kRunNoises = 3.0;

// The points that agree (|gain| <= tau) where the surface below moved by s
// rises by over `run` (a slope) to the next point and again to the one
// after, the same way, but not by over `single` to the next (Settle's
// single steep points, counted already).
// RunFeatures' count on the surface below at the points (`under`, NaN
// where unknown).
int RunFeaturesAt(std::span<const float> x, std::span<const float> z, std::span<const float> under, double tau,
                  double run, double single) {
  const auto slope = [&](std::size_t i) { return (under[i + 1] - under[i]) / (x[i + 1] - x[i]); };
  int features = 0;
  for (std::size_t i = 0; i + 2 < x.size(); ++i) {
    if (!(std::abs(z[i] - under[i]) <= tau)) continue;
    const double first = slope(i), second = slope(i + 1);
    features += std::abs(first) > run && std::abs(first) <= single && first * second > 0.0 && std::abs(second) > run;
  }
  return features;
}

int RunFeatures(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double s, double tau,
                double run, double single, const PointsOnGrid* grid) {
  thread_local std::vector<float> under;
  if (grid) {
    grid->BelowAt(s, under);
  } else {
    under.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) under[i] = static_cast<float>(below.At(x[i] - s));
  }
  return RunFeaturesAt(x, z, under, tau, run, single);
}

void Settle(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, const RegistrationScale& k,
            const AddedBeadOptions& o, const PointsOnGrid* grid, Registration& r) {
  double sum = 0.0;
  int features = 0;
  const double noise_slope = k.noise / k.spacing, feature_slope = kFeatureSigmas * std::sqrt(2.0) * noise_slope;
  r.points = 0;
  if (grid) {
    const PointsOnGrid::Agreement a = grid->Agree(r.shift, k.tau, feature_slope);
    sum = a.sum_d2, r.points = a.points, features = a.features;
  } else {
    for (std::size_t i = 0; i < x.size(); ++i) {
      const SurfaceGrid::Sample b = below.SampleAt(x[i] - r.shift);
      const double d = z[i] - b.z;
      if (!(std::abs(d) <= k.tau)) continue;
      sum += d * d, ++r.points;
      features += std::abs(b.slope) > feature_slope;
    }
  }
  if (features < o.min_feature_points)
    features += RunFeatures(x, z, below, r.shift, k.tau, kRunNoises * noise_slope, feature_slope, grid);
  r.rms = r.points ? std::sqrt(sum / r.points) : Registration::kNaN;
  r.sigma = std::max(r.sigma, r.hidden_sigma);
  r.constrained = !r.at_end && r.sigma <= o.max_shift_sigma_mm && features >= o.min_feature_points;
}

// The shift: the middle of the shifts whose (smoothed) cost is within 1 of
// the least; its sigma: half the range within 4 (two sigmas of one
// parameter), over two, and at least a wall's sampling, spacing / sqrt 12.
// A range that reaches the search's end leaves the shift unconstrained
// (nothing outside the bead to register on: a bare bed).
Registration FromCurve(const CostCurve& curve, const RegistrationScale& k) {
  const std::vector<double> cost = Smoothed(curve, 2);
  const double least = *std::min_element(cost.begin(), cost.end()), cap = k.Cap();
  double lo1 = 1e300, hi1 = -1e300, lo4 = 1e300, hi4 = -1e300, lo_cap = 1e300, hi_cap = -1e300;
  Registration r;
  for (std::size_t i = 0; i < cost.size(); ++i) {
    if (cost[i] <= least + 1.0) lo1 = std::min(lo1, curve.s[i]), hi1 = std::max(hi1, curve.s[i]);
    if (cost[i] <= least + 4.0) {
      lo4 = std::min(lo4, curve.s[i]), hi4 = std::max(hi4, curve.s[i]);
      r.at_end = r.at_end || i == 0 || i + 1 == cost.size();
    }
    if (cost[i] <= least + cap) {
      lo_cap = std::min(lo_cap, curve.s[i]), hi_cap = std::max(hi_cap, curve.s[i]);
      r.bracket_open = r.bracket_open || i == 0 || i + 1 == cost.size();
    }
  }
  r.shift = 0.5 * (lo1 + hi1);
  r.sigma = std::max(0.25 * (hi4 - lo4), k.spacing / std::sqrt(12.0));
  r.hidden_sigma = (hi_cap - lo_cap) / std::sqrt(12.0);
  return r;
}

using Local = PointsOnGrid::Local;

// Gauss-Newton from `start`, each step halved until the cost falls (at
// most kHalvings times: where none falls the least is within that of s, a
// kink of the truncated cost); false where it leaves the warm window,
// finds no slope to move on, or does not settle in a few steps.
constexpr int kHalvings = 3;

bool Track(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, const RegistrationScale& k,
           const AddedBeadOptions& o, double start, const PointsOnGrid* grid, Registration& r) {
  double s = start;
  Local here = LocalCost(x, z, below, s, k, grid);
  for (int iteration = 0; iteration < 8; ++iteration) {
    if (!(here.curvature > 0.0)) return false;
    double step = -here.gradient / here.curvature;
    bool settled = std::abs(step) < 1e-3 * k.spacing;
    for (int halving = 0; !settled; ++halving, step *= 0.5) {
      if (halving > kHalvings) {
        settled = true;
        break;
      }
      const Local there = LocalCost(x, z, below, s + step, k, grid);
      if (there.cost > here.cost) continue;
      s += step, here = there;
      if (std::abs(s - start) > o.warm_half_mm) return false;
      break;
    }
    if (settled) {
      r.shift = s;
      // cost ~ least + (s - s0)^2 / sigma^2 with curvature 2 / sigma^2.
      r.sigma = std::max(std::sqrt(2.0 / here.curvature), k.spacing / std::sqrt(12.0));
      r.tracked = true;
      return true;
    }
  }
  return false;
}

// The widest range searched: a quarter of the surface below's span (each
// shift's cost then counts at least its middle half: the points compared
// are those every shift keeps over the surface below), at least
// +-max_shift_mm.
double WidestSearch(const SurfaceGrid& below, const AddedBeadOptions& o) {
  return std::max(o.max_shift_mm, 0.25 * (below.last_mm() - below.first_mm()));
}

// The range searched about `centre`: +-first_half, doubled while the
// least lies within the warm window of its end (the cost may fall further
// beyond it), up to the widest. A least still within the window of the
// range's end is not trusted (at_end: not constrained).
Registration Searched(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                      const RegistrationScale& k, const AddedBeadOptions& o, const PointsOnGrid* grid, double centre,
                      double first_half) {
  const double widest = WidestSearch(below, o);
  double half = first_half;
  Registration r = FromCurve(Scan(x, z, below, centre, half, k, grid), k);
  while (std::abs(r.shift - centre) > half - o.warm_half_mm && std::abs(centre) + 2.0 * half <= widest) {
    half *= 2.0;
    r = FromCurve(Scan(x, z, below, centre, half, k, grid), k);
  }
  r.at_end = r.at_end || std::abs(r.shift - centre) > half - o.warm_half_mm;
  Settle(x, z, below, k, o, grid, r);
  return r;
}

// Whether the pass's shift may lie beyond the first range: over the widest
// at four point spacings (a coarse look: a lower bead's top, the most of
// what shows beside a bead laid far off it, agrees within the threshold
// where its slope is under tau / (2 spacings), most of an ellipse's top at
// the twin's 0.06 mm and 0.05 mm; the fine search decides), the least
// cost outside +-(max_shift_mm - warm_half_mm) is under the least inside
// by more than one point's disagreement (the cap). A bead laid 4-6 mm off
// the one below shows a false least inside +-3 mm, its sigma 0.02 (the
// layer below's bead hidden under the new one, its own visible beside it
// counted as disagreeing), which the doubling about the range's end does
// not see.
bool FarLeast(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, const RegistrationScale& k,
              const AddedBeadOptions& o, const PointsOnGrid* grid) {
  const double widest = WidestSearch(below, o), inner = o.max_shift_mm - o.warm_half_mm;
  if (widest <= o.max_shift_mm) return false;
  double least_in = INFINITY, least_out = INFINITY;
  const double step = std::max(4.0 * k.spacing, 1e-3);
  for (double s = -widest; s <= widest + 1e-12; s += step) {
    const double c = TruncatedCost(x, z, below, s, k, widest, grid);
    double& least = std::abs(s) > inner ? least_out : least_in;
    least = std::min(least, c);
  }
  return least_out + k.Cap() < least_in;
}

// The options' bounds in mm, set for the twin's sensor (points 0.05 mm
// apart over 40 mm), fitted to this one's:
//  - a shift's sigma is never under spacing / sqrt 12 (a lone wall's
//    sampling): one spacing at least bounds it, and the warm window holds
//    six. (Fixed in mm, a sensor's points 0.2 mm apart on a 24 mm bead had
//    every shift refused, its sigma's floor 0.058 mm over the 0.05
//    allowed: no wander reported on any layer, and a layer whose search
//    then went astray measured 1.7 times its area.)
//  - the first range is at most the widest (a quarter of the surface
//    below's span). (Over a field of +-2 mm, a glue bead's, +-3 mm left no
//    point that every shift keeps over the surface below: every cost 0,
//    every shift refused.)
AddedBeadOptions AtSampling(const AddedBeadOptions& o, double spacing, const SurfaceGrid& below) {
  AddedBeadOptions at = o;
  at.max_shift_sigma_mm = std::max(o.max_shift_sigma_mm, spacing);
  at.warm_half_mm = std::max(o.warm_half_mm, 6.0 * spacing);
  at.max_shift_mm = std::min(o.max_shift_mm, 0.25 * (below.last_mm() - below.first_mm()));
  at.warm_half_mm = std::min(at.warm_half_mm, 0.5 * at.max_shift_mm);
  return at;
}

}  // namespace

PointsOnGrid::Local LocalCost(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double s,
                              const RegistrationScale& k, const PointsOnGrid* grid) {
  const double noise2 = k.noise * k.noise, cap = k.Cap();
  if (grid) return grid->LocalCost(s, noise2, cap);
  PointsOnGrid::Local l;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const SurfaceGrid::Sample b = below.SampleAt(x[i] - s);
    const double d = z[i] - b.z;
    if (std::isnan(d)) {
      l.cost += cap;
      continue;
    }
    const double v = noise2 * (1.0 + b.variance), chi2 = d * d / v;
    if (chi2 >= cap) {
      l.cost += cap;
      continue;
    }
    const double g = b.slope;
    l.cost += chi2;
    l.gradient += 2.0 * d * g / v;
    l.curvature += 2.0 * g * g / v;
  }
  return l;
}

Registration Register(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                      const RegistrationScale& k, const AddedBeadOptions& options, const double* start,
                      const PointsOnGrid* grid, double start_hidden_sigma, bool search_wide) {
  const AddedBeadOptions o = AtSampling(options, k.spacing, below);
  // The new points on the surface below's grid, where they lie on it: the
  // costs eight points at a time (part/grid_costs.h).
  thread_local PointsOnGrid on_grid;
  if (!grid && on_grid.Make(x, z, below)) grid = &on_grid;
  if (start && std::abs(*start) + o.warm_half_mm < WidestSearch(below, o)) {
    Registration r;
    r.hidden_sigma = start_hidden_sigma;
    if (Track(x, z, below, k, o, *start, grid, r)) {
      Settle(x, z, below, k, o, grid, r);
      if (r.constrained) return r;
    }
    r = FromCurve(Scan(x, z, below, *start, o.warm_half_mm, k, grid), k);
    Settle(x, z, below, k, o, grid, r);
    if (!r.at_end && (r.constrained || !r.bracket_open)) return r;
  }
  // A pass found beyond the first range is searched about its shift; one
  // not found yet, over the widest where asked and a least lies there.
  if (start && std::abs(*start) > o.max_shift_mm - o.warm_half_mm)
    return Searched(x, z, below, k, o, grid, *start, o.max_shift_mm);
  if (!start && search_wide && FarLeast(x, z, below, k, o, grid))
    return Searched(x, z, below, k, o, grid, 0.0, WidestSearch(below, o));
  return Searched(x, z, below, k, o, grid, 0.0, o.max_shift_mm);
}

void SettleShift(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                 const RegistrationScale& scale, const AddedBeadOptions& options, const PointsOnGrid* grid,
                 Registration& r) {
  Settle(x, z, below, scale, options, grid, r);
}

int FlankPoints(std::span<const float> x, std::span<const float> z, std::span<const float> under,
                const RegistrationScale& k, int enough) {
  const double noise_slope = k.noise / k.spacing, feature_slope = kFeatureSigmas * std::sqrt(2.0) * noise_slope;
  // Both of Settle's rules in one pass (part/part_kernel.h flanks), in
  // floats, each rise to the next point against what a slope gives over
  // that spacing; the last point by the first rule alone. Counted a stretch
  // of kStretch points at a time, until the first rule alone has enough
  // (what the count is for: a profile whose flanks lie left of its middle
  // is not read to its end).
  constexpr std::size_t kStretch = 128;
  const auto tau = static_cast<float>(k.tau), steep = static_cast<float>(feature_slope);
  const PartKernel& kernel = ActivePartKernel();
  int single = 0, runs = 0;
  const std::size_t n = x.size();
  for (std::size_t lo = 0; lo + 2 < n && single < enough; lo += kStretch) {
    const std::size_t len = std::min(kStretch + 2, n - lo);
    const GridSums counts = kernel.flanks(x.data() + lo, z.data() + lo, under.data() + lo, len, tau, steep,
                                          static_cast<float>(kRunNoises * noise_slope));
    single += static_cast<int>(counts.first), runs += static_cast<int>(counts.second);
  }
  if (n >= 2) {
    const std::size_t i = n - 2;
    const float d = z[i] - under[i];
    single += (d <= tau && d >= -tau) && std::abs(under[i + 1] - under[i]) > steep * (x[i + 1] - x[i]);
  }
  return single < enough ? single + runs : single;
}

}  // namespace bead::part
