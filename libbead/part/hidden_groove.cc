#include "libbead/part/hidden_groove.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "libbead/core/float_bits.h"
#include "libbead/core/median.h"
#include "libbead/part/outline_fit.h"
#include "libbead/part/part_kernel.h"
#include "libbead/part/silhouette.h"
#include "libbead/part/superellipse.h"

namespace bead::part {
namespace {

// The groove: the bead's lower outline above the surface below, by the
// midpoint rule, a hundred steps across each half of the bead (off by
// the square of a step where the outline crosses the surface below, a
// kink: well under a point's noise); with its gradient in x0, z0, a and b,
// the sum's own (its nodes x = x0 + a u_k move with the bead, s = s(u_k),
// part/superellipse.h): over the nodes where the outline stands above the
// surface below, a step times 1 for z0, -s for b, -old'(x) for x0; and
// groove / a less a step times old'(x) u for a; and in the exponent, a step
// times -b ds/dp. Beside them, the surface below's variance (in one point's)
// integrated over those nodes, and the outline's lowest stand over the
// surface below (negative: sunk into it; infinite: nowhere known).
//
// And, for a profiler whose points average over a footprint (Around::
// footprint), the variance of where the surface below steps between its
// points under the groove. Beside the layer below's wall the surface seen
// drops down the column its overhang hides (to the bed, or a lower layer's
// shoulder: deeper layer by layer) between two points a spacing h apart.
// Read as the straight line between the two, a step of depth d anywhere in
// between alike misses the groove by d (place - middle): variance d^2 h^2
// / 12. Over the nodes: a node dx wide on a run of slope S holds its share
// dx / h of (S h)^2 h^2 / 12; S min(S h, 2 f) h^2 dx / 12 with f the
// outline's stand there, so that where the outline crosses the step's
// line the sum is the same d^2 h^2 / 12 with d its stand over the step's
// foot (3/4 of it where it just clears the step's top). h: the new points'
// spacing, the sensor's (the layer below's as well). (Left out, the
// corrected areas' errors grew layer by layer with the column under a
// footprint and their sigmas did not: on a generator's contours of 6-12
// tamped or pressed layers, its spot as wide as the spacing, the fifth of
// the rows with the most hidden were 0.08-0.14 mm^2 off at sigmas of
// 0.04-0.06 and the worst layers' intervals covered 72-84 %; the errors'
// excess over the sigmas there, 0.08-0.11 mm^2, is this term's size, its
// median 0.07-0.12: with it, those layers 94.7-99.3 %. The same wall
// without noise kept the excess (0.063 mm^2 at 0.039); its points not
// averaged, the excess was gone, noise or none (0.02-0.04 mm^2 at
// 0.05-0.07), as on the twin's walls, whose deep rows' errors lie under
// their sigmas: there the term is not added. Where the step lies should
// cancel between the area seen and the groove, which read the same line
// across it; why under a spot it does not, I did not pin down: the ends'
// places explain about a third of the excess.)
struct GrooveSum {
  double groove = 0.0;
  double lowest = INFINITY;
  double gradient[4] = {};      // x0, z0, a, b
  double by_exponent = 0.0;     // mm^2 per unit of p
  double variance_under = 0.0;  // mm
  double steps_under = 0.0;     // mm^4: the steps' variance (below)
};

// steps_spacing: h for the steps' variance (0: not summed, no footprint).
GrooveSum GrooveWithGradient(const Ellipse& e, const SurfaceGrid& below, double shift, double steps_spacing) {
  const SurfaceGrid::Shifted under(below, shift);
  const SuperellipseTable& shape = SuperellipseOf(e.p);
  constexpr int kNodes = SuperellipseTable::kNodes;
  constexpr double kDu = 2.0 / kNodes;
  const auto &node_u = shape.node_u(), &node_s = shape.node_s(), &node_ds_dp = shape.node_ds_dp();
  double sum = 0.0, on = 0.0, s_on = 0.0, slope_on = 0.0, slope_u_on = 0.0, variance = 0.0, dp_on = 0.0, steps = 0.0;
  double lowest = INFINITY;
  // The surface below at every node first, four a register.
  std::array<double, kNodes> xs, zs;
  for (int k = 0; k < kNodes; ++k) xs[k] = e.x0 + e.a * node_u[k];
  ActivePartKernel().rows_at(xs.data(), kNodes, under.Rows(), zs.data());
  // A stadium's flat bottom is pressed onto what lies under it (a tamped
  // bead's: the tamper holds its top, the melt fills down to the surface
  // below, over a lower bead's rounded side too): no groove under it, only
  // under its rounded ends (|u| > 1 - c, part/superellipse.h). (Counted as
  // a void there, a generator's tamped beads laid 0.5-1 mm off the one
  // below came out 0.2-0.3 mm^2 low, a quarter of their intervals missing.)
  const double flat = IsStadium(e.p) ? 1.0 + e.p : -1.0;
  for (int k = 0; k < kNodes; ++k) {
    const double u = node_u[k], s = node_s[k];
    const double x = xs[k], f = e.z0 - e.b * s - zs[k];
    lowest = f < lowest ? f : lowest;                // (NaN where not known: left out)
    if (!(f > 0.0) || std::abs(u) < flat) continue;  // the surface below above the outline, or not known
    const SurfaceGrid::Sample old = under.At(x);     // its slope and variance, where they count
    sum += f, on += 1.0, s_on += s, slope_on += old.slope, slope_u_on += old.slope * u, variance += old.variance;
    const double rise = std::abs(old.slope);
    if (steps_spacing > 0.0 && std::isfinite(rise)) steps += rise * std::min(rise * steps_spacing, 2.0 * f);
    dp_on += node_ds_dp[k];
  }
  const double step = e.a * kDu;
  GrooveSum g;
  g.groove = sum * step;
  g.variance_under = variance * step;
  g.steps_under = steps * step * steps_spacing * steps_spacing / 12.0;
  g.gradient[0] = -slope_on * step;
  g.gradient[1] = on * step;
  g.gradient[2] = sum * kDu - slope_u_on * step;
  g.gradient[3] = -s_on * step;
  g.by_exponent = -e.b * dp_on * step;
  g.lowest = lowest;
  return g;
}

// Whether the shape placed on the bead is one it can have (hidden_groove.h:
// OutlineMisfit; the top's residual is judged over the layer's pool, not
// here); height, the bead's.
OutlineMisfit MisfitOf(const GrooveSum& g, double height, double exponent) {
  if (std::isfinite(g.lowest) && g.lowest > kFloatsHeights * height) return OutlineMisfit::kFloats;
  // (Within a thousandth of either end of its family's grid; a stadium's
  // p is negative, its grid's ends c = 0.1 and 1.59.)
  const std::vector<double>& family = GridOf(exponent);
  const auto near = [&](double end) { return std::abs(exponent - end) <= 1e-3 * std::abs(end); };
  if (near(family.front()) || near(family.back())) return OutlineMisfit::kFamilyEdge;
  return OutlineMisfit::kNone;
}

// What the groove's sigma is made of beyond the fit's own covariance.
struct Around {
  const SurfaceGrid& below;
  double shift, shift_sigma, spacing, aspect_sigma;
  double noise_mm;  // one point's noise (the grid's variance is in its square)
  // A held exponent's sigma (0: an ellipse's, by assumption) and its
  // errors' correlation with the aspect's (PooledShape).
  double exponent_sigma = 0.0, correlation = 0.0;
  bool footprint = false;
  // The spacing the surface below's steps are counted at (GrooveSum::
  // steps_under): only under a footprint.
  double StepsSpacing() const { return footprint ? spacing : 0.0; }
};

// The groove's variance from what lies around the ellipse: the surface
// below known to its own noise (its grid's variance in one point's noise,
// one independent value per point spacing), where it steps between its
// points (GrooveSum::steps_under) and its place to the shift's sigma.
// seen_by_shift: the area seen's own derivative in the shift, where
// it is counted with the groove's (0: the groove's alone).
double AroundVariance(const GrooveSum& sum, const Around& o, double seen_by_shift = 0.0) {
  // One value a point spacing, its variance the integral's over the groove
  // (the nodes': the sum over spacings it stands for).
  const double below_var = o.noise_mm * o.noise_mm * sum.variance_under * o.spacing;
  // The surface below moved by the shift is the ellipse moved the other
  // way: the groove's derivative in the shift is minus its x0's, the area
  // seen less the groove's that plus seen_by_shift.
  const double by_shift = (seen_by_shift + sum.gradient[0]) * o.shift_sigma;
  return below_var + by_shift * by_shift + sum.steps_under;
}

// The fitted groove's 1-sigma: the fit's covariance (s2 (J^T J)^-1)
// through the groove's gradient; what lies around it (AroundVariance);
// a held aspect to its pooled sigma: each moves the groove as the fit's
// own error does. NaN where the fit cannot place the bead's sides (J^T J
// singular).
double GrooveSigma(const Ellipse& e, const FitShape& shape, const Eigen::Matrix4d& JtJ, double s2, const GrooveSum& sum,
                   const Around& o, double seen_by_shift) {
  const auto k = static_cast<Eigen::Index>(shape.Params());
  Eigen::FullPivLU<Eigen::MatrixXd> lu(JtJ.topLeftCorner(k, k));
  if (!lu.isInvertible()) return NAN;
  const Eigen::MatrixXd cov = s2 * lu.inverse();
  // The groove's gradient in the fitted parameters (b following a where
  // the aspect is held).
  Eigen::VectorXd grad(static_cast<Eigen::Index>(shape.Params()));
  for (std::size_t i = 0; i < shape.Params(); ++i) grad[static_cast<Eigen::Index>(i)] = sum.gradient[i];
  if (std::isfinite(shape.aspect)) grad[2] += shape.aspect * sum.gradient[3];
  // A held aspect a sigma off moves b by a times that sigma: the groove's
  // derivative in b times it (the groove is linear in b over the nodes
  // where the outline stands above the surface below, and a change of a
  // few per cent moves few nodes in or out; the integral at the aspect
  // plus a sigma gave the same coverage, 4726 of 4800).
  const double by_aspect =
      std::isfinite(shape.aspect) && o.aspect_sigma > 0.0 ? sum.gradient[3] * e.a * o.aspect_sigma : 0.0;
  // A held exponent a sigma off, the same way, with the aspect's error
  // correlated.
  const double by_exponent = sum.by_exponent * o.exponent_sigma;
  const double shape_var =
      by_aspect * by_aspect + by_exponent * by_exponent + 2.0 * o.correlation * by_aspect * by_exponent;
  return std::sqrt(std::max(0.0, grad.dot(cov * grad)) + AroundVariance(sum, o, seen_by_shift) +
                   std::max(0.0, shape_var));
}

// The RMS of the seen top's points about the fitted ellipse's top: those
// within 0.9 of its half-width where it stands over the surface below (as
// the silhouette's, part/silhouette.h: the fit's own residual counts the
// walls, lost points' edges and the bare surface too); NaN where none.
double TopRms(const Window& w, const Ellipse& e) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t j = 0; j < w.x.size(); ++j) {
    if (!(std::abs(w.x[j] - e.x0) <= 0.9 * e.a)) continue;
    const double top = e.z0 + e.Half(w.x[j]);
    if (!(top > w.old[j])) continue;
    sum += (w.z[j] - top) * (w.z[j] - top), ++n;
  }
  return n ? std::sqrt(sum / n) : NAN;
}

// The area seen's derivative in the shift where the bead is fitted: the
// surface below's rise under it, from its left end to its right one (the
// outermost points of the run of gains over `run` around its centre), as
// at the silhouette (its walls' heights over the surface below). (Left
// out, a twin contour's layer whose beads lay on the bed beside the one
// below and on its shoulder, the surface below rising 2.4 mm under them,
// registered 0.022 mm off at a sigma of 0.014, had its areas seen 0.06
// mm^2 low at sigmas of 0.01: 40 % covered.)
double SeenByShift(const Window& w, double center, double run) {
  const auto mid = static_cast<std::size_t>(std::lower_bound(w.x.begin(), w.x.end(), center) - w.x.begin());
  if (mid >= w.x.size() || !(w.Gain(mid) > run)) return 0.0;
  std::size_t left = mid, right = mid;
  while (left > 0 && w.Gain(left - 1) > run) --left;
  while (right + 1 < w.x.size() && w.Gain(right + 1) > run) ++right;
  return w.old[right] - w.old[left];
}

// A stadium's flat bottom is pressed onto what lies under it
// (GrooveWithGradient): where that holds a flat under the flat part, the
// bottom lies on it, and the bead's half-height is half its top's height
// over it, b = (z0 + b - level) / 2, read from every point of the top and
// of that flat, not from the few points on the ends' arcs that the top's
// solve reads b from. (At 0.2 mm spacing, three a side on a tamped bead's
// 1 mm arcs, a 10 um noise spread the rows' solved b by 0.14-0.19 mm, and
// their median lay 3-9 % high on every layer of a generator's wall, the
// ends placed outward with the arcs taller; the layers' corrected areas
// came out 0.8-2.3 % high. This one: 0.003 mm about 1.0006 for 1.) The
// flat: the surface below's points under the flat part within two of a
// point's noise of their median, their mean the level; the bottom may
// overhang a drop (a lower bead's rounded side where the bead wandered
// off it: the melt fills down), but the flat holds most of its points, and
// none stands above the level by three noises (into the bottom). NaN
// where the shape is no stadium, or the flat holds fewer than
// kPressedPoints points, or fewer than half.
constexpr std::size_t kPressedPoints = 5;

double PressedHalfHeight(const Window& w, const Ellipse& e, double noise_mm) {
  if (!IsStadium(e.p)) return NAN;
  const double flat = (1.0 + e.p) * e.a;  // the flat part's half-width, (1 - c) a
  thread_local std::vector<double> under;
  under.clear();
  for (std::size_t j = 0; j < w.x.size(); ++j)
    if (std::abs(w.x[j] - e.x0) < flat) under.push_back(w.old[j]);
  if (under.size() < kPressedPoints) return NAN;
  const double median = MiddleInPlace(under);
  double sum = 0.0, top = -INFINITY;
  std::size_t on = 0;
  for (const double v : under) {
    top = std::max(top, v);
    if (std::abs(v - median) <= 2.0 * noise_mm) sum += v, ++on;
  }
  if (on < kPressedPoints || 2 * on < under.size()) return NAN;
  const double level = sum / static_cast<double>(on);
  return top <= level + 3.0 * noise_mm ? 0.5 * (e.z0 + e.b - level) : NAN;
}

// The groove of the ellipse placed at the bead's silhouette (no fit).
HiddenGroove AtTheSilhouette(const Silhouette& s, const Around& o, const PooledShape* held, double center, double base,
                             double height) {
  HiddenGroove out;
  const GrooveSum groove = GrooveWithGradient(s.e, o.below, o.shift, o.StepsSpacing());
  out.hidden_mm2 = groove.groove;
  out.seen_adjust_mm2 = s.seen_adjust;
  // The area seen stands on the same surface below, between the ends: moved
  // by the shift, it changes by the surface below's rise from the left end
  // to the right one (the ends stay at the walls the data show).
  const double seen_by_shift = s.wall_left - s.wall_right;
  const double var =
      SilhouetteVariance(s, held, groove.gradient, groove.by_exponent) + AroundVariance(groove, o, seen_by_shift);
  out.sigma_mm2 = std::sqrt(var);
  out.at_silhouette = true;
  out.aspect = s.aspect, out.exponent = s.exponent;
  out.aspect_end_var = s.aspect_end_var, out.exponent_end_var = s.exponent_end_var, out.left_end_mm = s.e.x0 - s.e.a;
  out.aspect_grid_var = s.aspect_grid_var, out.exponent_grid_var = s.exponent_grid_var;
  out.aspect_mixed_var = s.aspect_mixed_var, out.exponent_mixed_var = s.exponent_mixed_var;
  out.shape_consistent = s.shape_consistent, out.family_log_ratio = s.family_log_ratio;
  out.end_mixed = s.end_mixed[0] || s.end_mixed[1];
  out.end_place[0] = s.end_place[0], out.end_place[1] = s.end_place[1];
  out.dx0 = s.e.x0 - center, out.dz0 = s.e.z0 - base, out.a = s.e.a, out.b = s.e.b, out.shape_a = s.shape_a;
  out.top_rms_mm = std::sqrt(s.residual_variance);
  out.misfit = MisfitOf(groove, height, s.exponent);
  out.ok = std::isfinite(out.hidden_mm2) && std::isfinite(out.sigma_mm2) && out.misfit == OutlineMisfit::kNone;
  return out;
}

}  // namespace

HiddenGroove EstimateHiddenGroove(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                                  double shift, double shift_sigma, double noise_mm, double center, double width,
                                  double height, const PooledShape* pooled, const HiddenGroove* previous,
                                  double free_exponent, bool stadium_only) {
  HiddenGroove out;
  if (!(width > 0.0) || !(height > 0.0)) return out;
  if (pooled && pooled->top_noise > kTopOffNoise) {
    out.misfit = OutlineMisfit::kTopOff;  // the layer's shape is not its beads'
    return out;
  }
  if (pooled && pooled->ends_off) {
    out.misfit = OutlineMisfit::kEndsOff;  // no shape of the family has their tops and walls
    return out;
  }
  // The points within a width of the centre (x increasing: a range).
  thread_local Window w;
  const auto first = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), center - width) - x.begin());
  const auto end = static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), center + width) - x.begin());
  // Each written in place, kept where the surface below is known (the
  // next overwrites one that is not).
  const std::size_t span = std::max(first, end) - first;
  w.x.resize(span), w.z.resize(span), w.old.resize(span);
  for (std::size_t j = 0; j < span; ++j) w.x[j] = x[first + j];
  ActivePartKernel().rows_at(w.x.data(), span, SurfaceGrid::Shifted(below, shift).Rows(), w.old.data());
  std::size_t n = 0;
  for (std::size_t j = 0; j < span; ++j) {
    const double old = w.old[j];
    const float zj = z[first + j];
    w.x[n] = w.x[j], w.z[n] = zj, w.old[n] = old;
    // (By the bits, core/float_bits.h: std::isfinite was a fifth of this loop.)
    n += static_cast<std::size_t>(IsFiniteBits(old)) & static_cast<std::size_t>(IsFiniteBits(zj));
  }
  w.x.resize(n), w.z.resize(n), w.old.resize(n);
  if (w.x.size() < 12) return out;
  const double spacing = (w.x.back() - w.x.front()) / static_cast<double>(w.x.size() - 1);
  const double base = below.At(center - shift);
  // A fit holds the pooled exponent where it is not an ellipse's (else 2;
  // with none pooled, the one it is given).
  const bool superellipse = pooled && pooled->NotAnEllipse();
  const double exponent = superellipse ? pooled->exponent : pooled ? 2.0 : free_exponent;
  const Around around{below,
                      shift,
                      shift_sigma,
                      spacing,
                      pooled ? pooled->aspect_sigma : 0.0,
                      noise_mm,
                      superellipse ? pooled->exponent_sigma : 0.0,
                      superellipse ? pooled->correlation : 0.0,
                      pooled && pooled->footprint};
  // Placed at its silhouette where the bead shows one (part/silhouette.h):
  // its run over 3 sigmas of a point's noise and 2 % of its height; each
  // end's wall rising over 6 sigmas (a difference of two points' noise at
  // over 4) and 15 % of its height. (The first values tried, not tuned:
  // the walls' and contours' figures were read once, with these.)
  const SilhouetteScale scale{std::max(3.0 * noise_mm, 0.02 * height), std::max(6.0 * noise_mm, 0.15 * height)};
  const double* start_place = previous && previous->ok ? previous->end_place : nullptr;
  FreeSolve free{stadium_only};
  if (const Walls walls = AtTheWalls(w, center, scale, pooled, start_place, free, TopScale{noise_mm, height, spacing});
      walls.largest) {
    const Silhouette& s = walls.other ? *walls.other : *walls.largest;
    HiddenGroove placed = AtTheSilhouette(s, around, pooled, center, base, height);
    // Placed at another rise, the data favour it by its top alone: half the
    // two placements' difference in the area is in the sigma.
    if (walls.other) {
      const HiddenGroove largest = AtTheSilhouette(*walls.largest, around, pooled, center, base, height);
      const double doubt =
          0.5 * ((placed.seen_adjust_mm2 - placed.hidden_mm2) - (largest.seen_adjust_mm2 - largest.hidden_mm2));
      placed.sigma_mm2 = std::isfinite(doubt) ? std::hypot(placed.sigma_mm2, doubt) : NAN;
      placed.ok = placed.ok && std::isfinite(placed.sigma_mm2);
      placed.inside_cliff = true;
    }
    if (!pooled) placed.pressed_half_mm = PressedHalfHeight(w, s.e, noise_mm);
    return placed;
  }
  // Otherwise fitted: an ellipse, its aspect the layer's where held (and
  // its exponent, where that is not an ellipse's).
  const double held = pooled ? pooled->aspect : NAN;
  w.Close();
  FitShape shape{2.0 * spacing, held};
  // Started sunk to four depths (its centre on the surface below, a
  // quarter, half and three quarters of its height above) and two widths:
  // the least residual kept.
  Ellipse best;
  Eigen::Matrix4d JtJ, best_JtJ;               // the fits' J^T J (the fitted parameters' top left)
  double best_rss = INFINITY, best_top = NAN;  // best's TopRms, where taken
  // With the shape held, the neighbour's ellipse first: kept where it
  // fits as well as the neighbour's did; or where it does not, but the
  // start sunk half its height, 0.6 of the width across, fits no tenth
  // better: the profile itself fits worse than its neighbour (on the twin's
  // wall, 18 % of its rows; in 82 % of those all eight starts found no
  // tenth better either).
  bool warm = false;
  if (pooled && previous && previous->ok && std::isfinite(previous->fit_rms_mm)) {
    Ellipse e{center + previous->dx0, base + previous->dz0, previous->a, previous->b, exponent};
    best_rss = FitOutline(w, e, shape, best_JtJ), best = e;
    warm = std::sqrt(best_rss / static_cast<double>(w.x.size())) <= 1.2 * previous->fit_rms_mm;
    if (!warm) {
      Ellipse probe{center, base + 0.5 * height, 0.6 * width, 0.5 * height, exponent};
      const double rss = FitOutline(w, probe, shape, JtJ);
      warm = !(rss < 0.9 * best_rss);
      if (rss < best_rss) best_rss = rss, best = probe, best_JtJ = JtJ;
    }
    // And only where its top meets the points: the neighbour's bead carried
    // through a corner's exit on the twin's contour (the bead narrowing
    // from 3.6 to 3.0 mm across in 8 mm of path, hanging 3.9 mm off the
    // one below) stayed 0.6 mm too wide and 0.5 mm aside over 17 rows, its
    // top 10-15 tolerances off theirs (0.3-0.5 mm), their areas 1-4 mm^2
    // high at sigmas of 0.25; the eight starts found each row's bead.
    best_top = TopRms(w, best);
    warm = warm && best_top <= kTopOffNoise * TopTolerance(noise_mm, height);
  }
  for (double lift : {0.0, 0.25, 0.5, 0.75})
    for (double across : {0.5, 0.6}) {
      if (warm) break;
      Ellipse e{center, base + lift * height, across * width, height * (1.0 - lift), exponent};
      const double rss = FitOutline(w, e, shape, JtJ);
      if (rss < best_rss) best_rss = rss, best = e, best_JtJ = JtJ, best_top = NAN;
    }
  out.fit_rms_mm = std::sqrt(best_rss / static_cast<double>(w.x.size()));
  out.walls_unsolved = free.walls_unsolved, out.family_log_ratio = free.family_log_ratio;
  out.aspect = best.b / best.a, out.exponent = exponent;
  out.dx0 = best.x0 - center, out.dz0 = best.z0 - base, out.a = best.a, out.b = best.b;
  const GrooveSum groove = GrooveWithGradient(best, below, shift, around.StepsSpacing());
  out.hidden_mm2 = groove.groove;
  const double dof = static_cast<double>(w.x.size()) - static_cast<double>(shape.Params());
  out.sigma_mm2 =
      GrooveSigma(best, shape, best_JtJ, best_rss / dof, groove, around, SeenByShift(w, center, scale.floor));
  out.top_rms_mm = std::isnan(best_top) ? TopRms(w, best) : best_top;
  out.misfit = MisfitOf(groove, height, exponent);
  out.ok = std::isfinite(out.hidden_mm2) && std::isfinite(out.sigma_mm2) && out.misfit == OutlineMisfit::kNone;
  return out;
}

}  // namespace bead::part
