#include "libbead/part/silhouette.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "libbead/part/hidden_groove.h"
#include "libbead/part/silhouette_top.h"
#include "libbead/part/superellipse.h"

namespace bead::part {
namespace {

// A cell wider than this many of the window's spacings spans lost points.
constexpr double kGapSpacings = 1.5;
// The least share of the run over the floor a silhouette's walls span.
constexpr double kWallsOfRun = 0.8;

// The surface below at x, between the window's points j and j + 1.
double OldBetween(const Window& w, std::size_t j, double x) {
  const double t = (x - w.x[j]) / (w.x[j + 1] - w.x[j]);
  return w.old[j] + t * (w.old[j + 1] - w.old[j]);
}

// The step j (j to j + 1) of the rank-th largest rise over `least` among
// steps [from, to] (rises(j): the gain's rise toward the bead), the first
// of equals; false where there are not that many.
template <class Rise>
bool RankedWall(std::size_t from, std::size_t to, double least, int rank, Rise rises, std::size_t& wall) {
  thread_local std::vector<std::pair<double, std::size_t>> steps;
  steps.clear();
  for (std::size_t j = from; j <= to; ++j)
    if (const double rise = rises(j); rise > least) steps.push_back({-rise, j});
  if (std::ssize(steps) <= rank) return false;
  std::stable_sort(steps.begin(), steps.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  wall = steps[static_cast<std::size_t>(rank)].second;
  return true;
}

// The area seen from point `from` to point `to` (the trapezoids of the
// gains over 0).
double SeenBeyond(const Window& w, std::size_t from, std::size_t to) {
  double area = 0.0;
  for (std::size_t j = from; j < to; ++j)
    area += 0.5 * (std::max(w.Gain(j), 0.0) + std::max(w.Gain(j + 1), 0.0)) * (w.x[j + 1] - w.x[j]);
  return area;
}

// The groove's change from `from` to `to`, linear in the parameters.
double GrooveChange(const Ellipse& from, const Ellipse& to, const double gradient[4]) {
  double change = 0.0;
  for (std::size_t i = 0; i < 4; ++i) change += gradient[i] * (to[i] - from[i]);
  return change;
}

// An end placed with the shape held where the held shape's top fits the
// points best, searched over its cell a quarter spacing at a time and
// refined by a parabola (part/silhouette_top.h: SearchCell). In a gap
// (lost points beside its wall: nothing else says where the end is) it
// goes there, its cell narrowed to the width the residual's curvature
// places it within (at least a spacing). In a wall's own cell (`in_cell`)
// the end lies anywhere in it alike (a mean at the middle, a variance of
// cell^2 / 12) and the top's
// place is a measurement of it with the curvature's variance: the two
// combined, each in the other's variance (where the top places an end
// poorly, it stays near the middle); its cell stays the wall's.
// In a wall's own cell with points of the top, not spots' averages (no
// PooledShape::footprint), the top is read over the same points at every
// place (those within 0.9 of the half-width with the end at the cell's
// inner edge), and a least at the cell's first or last place is refined
// too. (Each place's top counted anew, the least was drawn to where the
// outermost point left it; with a least at an edge left at the middle,
// half the ends, those nearest a point, stayed at the middle (an eighth of
// a spacing apart, a quarter of them did, and the figures below came out
// the same as at a quarter): on a generator's tamped walls at
// 0.15-0.2 mm spacing, each layer's rows' error a sawtooth of up to +-0.15
// mm^2 across the ends' places in their cells. The rows' median error there
// fell by 10-55 %, the flow fits rose by up to 7 points.) Under a footprint,
// the points near an end are spots' averages and the least at an edge
// stays at the middle: the same points and edges there left fine tamped
// walls' intervals covering 1-2 points less (n12 89.4 % for 92.0, drops
// 89.8 for 93.5) for no closer rows; and an end that close to a point,
// read from the places nearest the edge as the top counted anew, made the
// twin's walls' rows' median error 0.16 % for 0.12 and a generator's wall's
// intervals cover 92.9 % for 97.3. (With the same points, the twin's wall's
// rows' median error is 0.013 mm^2 for 0.008, a tenth of a percent of its
// area for six hundredths: at a 0.05 mm cell, the ellipse held places an
// end near a point no closer than the cell's middle.) false where no place
// solves.
bool PlaceByTop(const Window& w, std::size_t first, std::size_t last, double spacing, const PooledShape& held, int side,
                bool in_cell, double& L, double& R, Silhouette& s) {
  const bool same_points = in_cell && std::isfinite(held.aspect) && !held.footprint;
  const std::optional<TopPlace> place = SearchCell(w, first, last, spacing, held, side, same_points, L, R, s);
  if (!place) return false;
  double& end = side ? R : L;
  const double lo = s.cell[2 * side], hi = s.cell[2 * side + 1];
  const double sigma2 = place->sigma2;
  if (in_cell) {
    const double middle = 0.5 * (lo + hi), uniform = (hi - lo) * (hi - lo) / 12.0;
    end = std::isfinite(sigma2) ? middle + (place->at - middle) * uniform / (uniform + sigma2) : middle;
    return true;
  }
  end = place->at;
  // The cell a uniform of the end's sigma (sqrt 12 of it wide).
  const double width = std::isfinite(sigma2) ? std::clamp(std::sqrt(12.0 * sigma2), spacing, hi - lo) : hi - lo;
  s.cell[2 * side] = std::max(lo, end - 0.5 * width), s.cell[2 * side + 1] = std::min(hi, end + 0.5 * width);
  return true;
}

// The area seen over a wall's cell (or gap) between points j and j + 1 as
// the placed bead e shows it (its top over the surface below, the surface
// beyond its end: the midpoint rule, 32 steps) less the trapezoid the area
// seen counted there (part/added_bead.h: the gains, each at least 0).
double CellSeenChange(const Window& w, std::size_t j, const Ellipse& e) {
  constexpr int kSteps = 32;
  const double lo = w.x[j], hi = w.x[j + 1], dx = (hi - lo) / kSteps;
  double model = 0.0;
  for (int k = 0; k < kSteps; ++k) {
    const double x = lo + (k + 0.5) * dx, old = OldBetween(w, j, x);
    if (std::abs(x - e.x0) < e.a) model += std::max(e.z0 + e.Half(x) - old, 0.0) * dx;
  }
  return model - 0.5 * (std::max(w.Gain(j), 0.0) + std::max(w.Gain(j + 1), 0.0)) * (hi - lo);
}

// Both ends placed with the held shape (PlaceByTop; in_cell where an end's
// cell is its wall's, not a gap), in turn, each with the other where it was
// last placed, until neither moves by a hundredth of a spacing: six passes
// at most where an end lies in a gap (each placed with the other at its
// gap's middle, both came out 0.01 mm outward), two where both lie in their
// walls' cells (on a generator's walls at 0.1 mm spacing, six moved the
// flow fits by 0.1 % and cost the part bench's 800-profile layers a
// quarter of their rate, 22.8 against 31.1 k profiles/s; one left the
// intervals covering 94.0-94.3 % for 94.3-95.3 %).
// false where one cannot be.
bool PlaceEndsByTop(const Window& w, std::size_t first, std::size_t last, double spacing, const PooledShape& held,
                    const bool gapped[2], double& L, double& R, Silhouette& s) {
  const double wall_cell[4] = {s.cell[0], s.cell[1], s.cell[2], s.cell[3]};
  const int passes = gapped[0] || gapped[1] ? 6 : 2;
  for (int pass = 0; pass < passes; ++pass) {
    double moved = 0.0;
    for (int side = 0; side < 2; ++side) {
      const double before = side ? R : L;
      s.cell[2 * side] = wall_cell[2 * side], s.cell[2 * side + 1] = wall_cell[2 * side + 1];
      if (!PlaceByTop(w, first, last, spacing, held, side, !gapped[side], L, R, s)) return false;
      moved = std::max(moved, std::abs((side ? R : L) - before));
    }
    if (moved < 0.01 * spacing) break;
  }
  return true;
}

// The free top solved over both families (part/superellipse.h), the
// stadium's kept only where the superellipse's least leaves a residual
// variance over the stadium's beyond four sigmas of that ratio (sqrt(2 /
// dof) each: two variances over the same m points, m - 2 degrees of
// freedom each), and over what any shape's top may leave, a share of the
// bead's height (part/hidden_groove.h: kTopShapeHeights): a top no
// superellipse follows. (The superellipse follows a tamped bead's top over
// |u| < 0.9, the stretch solved on, with b three times the bead's and 1.4-1.6
// times the noise; the stadium to the noise. Taken wherever the stadium's
// was four of its variances under, 19 of 50 rows of a twin's ellipses chose
// it, their ends at their cells' middles, not the bead's, and the pool of the
// other 31 said "toward a box", 2.012 +- 0.003. Noise-free, two tops a
// fraction of a cell off both fit to micrometres, one twice the other's.)
// grid: the family's kept. stadium_only: the stadium's alone.
std::ptrdiff_t SolveEitherFamily(const Window& w, std::size_t first, std::size_t last, double L, double R,
                                 Silhouette& s, const std::vector<double>*& grid, bool stadium_only) {
  double variance = NAN, stadium_variance = NAN;
  if (stadium_only) {
    s.family_log_ratio = NAN;  // (no evidence: one family tried)
    grid = &StadiumGrid();
    return SolveFree(w, first, last, L, R, s, EllipseIndex(StadiumGrid()), StadiumGrid(), &stadium_variance);
  }
  Silhouette stadium = s;
  grid = &SuperellipseGrid();
  const std::ptrdiff_t found = SolveFree(w, first, last, L, R, s, EllipseIndex(*grid), *grid, &variance);
  // The bead's height over the surface below at its top's middle; a top
  // the superellipse follows within its share, the stadium is not tried
  // (a twin's ellipses: none of their rows is).
  const double least = kTopShapeHeights * (s.e.z0 + s.e.b - w.old[(first + last) / 2]);
  if (found >= 0 && variance <= least * least) return found;
  const std::ptrdiff_t other =
      SolveFree(w, first, last, L, R, stadium, EllipseIndex(StadiumGrid()), StadiumGrid(), &stadium_variance);
  const double ratio = found >= 0 && other >= 0 ? std::log(variance / stadium_variance) : NAN;
  s.family_log_ratio = stadium.family_log_ratio = ratio;
  if (other < 0) return found;
  const double dof = std::max(1.0, static_cast<double>(TopPointCount(w, first, last, L, R)) - 2.0);
  if (found >= 0 && !(variance > (1.0 + 4.0 * std::sqrt(2.0 / dof)) * stadium_variance)) return found;
  s = stadium, grid = &StadiumGrid();
  return other;
}

}  // namespace

std::optional<Silhouette> AtSilhouette(const Window& w, double center, const SilhouetteScale& k,
                                       const PooledShape* held, const double* start_place, FreeSolve* free) {
  const std::size_t n = w.x.size();
  const auto c = static_cast<std::size_t>(std::lower_bound(w.x.begin(), w.x.end(), center) - w.x.begin());
  if (c >= n || !(w.Gain(c) > k.floor)) return std::nullopt;
  // The run around the centre standing over the floor.
  std::size_t l = c, r = c;
  while (l > 0 && w.Gain(l - 1) > k.floor) --l;
  while (r + 1 < n && w.Gain(r + 1) > k.floor) ++r;
  if (l == 0 || r + 1 == n || r - l < 8) return std::nullopt;
  // Each side's largest rise from one point to the next, in the run's
  // outer third (from the bare point beside it).
  const std::size_t third = (r - l) / 3;
  const auto rise_left = [&](std::size_t j) { return w.Gain(j + 1) - w.Gain(j); };
  const auto rise_right = [&](std::size_t j) { return w.Gain(j) - w.Gain(j + 1); };
  std::size_t jl = l - 1, jr = r;
  double rise_l = -INFINITY, rise_r = -INFINITY;
  for (std::size_t j = l - 1; j < l + third; ++j)
    if (const double rise = rise_left(j); rise > rise_l) rise_l = rise, jl = j;
  for (std::size_t j = r - third; j <= r; ++j)
    if (const double rise = rise_right(j); rise > rise_r) rise_r = rise, jr = j;
  if (!(rise_l > k.rise && rise_r > k.rise)) return std::nullopt;
  // Another of the rises (SilhouetteScale::wall_rank): where it lies inside
  // the largest, the area seen between the two is not the bead's (beyond
  // the largest, its foot, as there).
  double beyond = 0.0;
  if (const std::size_t largest = jl; k.wall_rank[0] > 0) {
    if (!RankedWall(l - 1, l + third - 1, k.rise, k.wall_rank[0], rise_left, jl)) return std::nullopt;
    if (jl > largest) beyond += SeenBeyond(w, largest, jl);
  }
  if (const std::size_t largest = jr; k.wall_rank[1] > 0) {
    if (!RankedWall(r - third, r, k.rise, k.wall_rank[1], rise_right, jr)) return std::nullopt;
    if (jr < largest) beyond += SeenBeyond(w, jr + 1, largest + 1);
  }
  // The walls span most of the run: a silhouette's widest point is the
  // bead's, and what stands over the floor beyond a wall is its foot. Walls
  // spanning less than kWallsOfRun of the run are steps on the bead (a bead
  // laid beside the one below, the old bead's flank making a step inside
  // its run, had it taken for its end: a half-width of 1.25 mm for 2.47,
  // corrected -41 % at 9 sigmas).
  if (w.x[jr + 1] - w.x[jl] < kWallsOfRun * (w.x[r + 1] - w.x[l - 1])) return std::nullopt;
  Silhouette s;
  s.cell[0] = w.x[jl], s.cell[1] = w.x[jl + 1], s.cell[2] = w.x[jr], s.cell[3] = w.x[jr + 1];
  s.over_cliff[0] = std::abs(w.old[jl + 1] - w.old[jl]) > rise_left(jl);
  s.over_cliff[1] = std::abs(w.old[jr + 1] - w.old[jr]) > rise_right(jr);
  // A wall that rises across missing points (a cell half as wide again as
  // the window's spacing: a triangulation shadow or a dropout beside it)
  // does not solve the bead's shape: the end lies anywhere in the gap, and
  // where (next to the wall, for a shadow the bead casts) is not the
  // cell's middle. With the shape held, the end is placed in the gap where
  // the top fits best (PlaceByTop), and the area seen's trapezoid across
  // the gap is replaced by what the bead placed shows there (seen_adjust).
  const double spacing = w.x[c + 1] - w.x[c];  // the points' own, at the bead's top
  const bool gapped[2] = {s.cell[1] - s.cell[0] > kGapSpacings * spacing,
                          s.cell[3] - s.cell[2] > kGapSpacings * spacing};
  const bool gap = gapped[0] || gapped[1];
  if (gap && !held) return std::nullopt;
  double L = 0.5 * (s.cell[0] + s.cell[1]), R = 0.5 * (s.cell[2] + s.cell[3]);
  // The widest point standing over the surface below by a wall at each
  // end: an overhang. (A bead whose sides meet the surface, seen at points
  // far apart, rises as steeply from one to the next; placed there, its
  // widest point lies on the surface.) With the shape free, by more: an end
  // placed half a cell inside the true one lets a bead lying on the surface
  // (an ellipse) be solved as one standing b sqrt(cell / a) higher, its
  // sides steepened by the exponent (at 0.2 mm spacing, a half ellipse lying
  // on the surface was placed as a box of p ~ 2.6 on a wall otherwise).
  const auto stands = [&](Silhouette& t, double lift) {
    t.wall_left = t.e.z0 - OldBetween(w, jl, L);
    t.wall_right = t.e.z0 - OldBetween(w, jr, R);
    return t.wall_left > k.rise + lift && t.wall_right > k.rise + lift;
  };
  if (held) {
    if (!PlaceEndsByTop(w, jl + 1, jr, spacing, *held, gapped, L, R, s)) return std::nullopt;
    if (!SolveHeld(w, jl + 1, jr, L, R, *held, s) || !stands(s, 0.0)) return std::nullopt;
    // Where the profiler averages over a footprint, the end lies within its
    // mixed point's spot: its cell stays the wall's (one spacing), only the
    // mix is told (the end anywhere in the cell: SilhouetteVariance).
    double widened[4] = {s.cell[0], s.cell[1], s.cell[2], s.cell[3]};
    OnTheTop(w, jl + 1, jr, s.e.z0, std::sqrt(s.residual_variance), gapped, held->footprint ? widened : s.cell,
             s.end_mixed);
    // The area seen across each wall's cell as the bead placed shows it.
    for (int side = 0; side < 2; ++side) s.seen_adjust += CellSeenChange(w, side ? jr : jl, s.e);
    s.seen_adjust -= beyond;
    return s;
  }
  const std::vector<double>* grid = nullptr;
  const std::ptrdiff_t found = SolveEitherFamily(w, jl + 1, jr, L, R, s, grid, free && free->stadium_only);
  const double cell = std::max(s.cell[1] - s.cell[0], s.cell[3] - s.cell[2]);
  if (found < 0 || !stands(s, s.e.b * std::sqrt(cell / s.e.a))) {
    if (free) free->walls_unsolved = true, free->family_log_ratio = s.family_log_ratio;
    return std::nullopt;
  }
  // The shape (for the layer's pool) with the ends placed by the top; the
  // bead itself stays placed at the cells' middles (its area seen counts
  // the walls' cells as trapezoids, which the middles match).
  ShapeByTop(w, jl + 1, jr, L, R, found, *grid, s, start_place);
  s.seen_adjust = -beyond;
  return s;
}

double TopScale::Over(const Silhouette& s) const {
  return TopMissTolerances(std::sqrt(s.residual_variance), noise_mm, height, s.aspect, spacing);
}

Walls AtTheWalls(const Window& w, double center, SilhouetteScale scale, const PooledShape* pooled,
                 const double* start_place, FreeSolve& free, const TopScale& top) {
  Walls out{AtSilhouette(w, center, scale, pooled, start_place, &free), std::nullopt};
  if (!out.largest || !(top.Over(*out.largest) > kTopOffNoise)) return out;
  const bool* cliff = out.largest->over_cliff;
  for (const auto [left, right] : {std::pair{1, 0}, {0, 1}, {1, 1}}) {
    if ((left && !cliff[0]) || (right && !cliff[1])) continue;
    scale.wall_rank[0] = left, scale.wall_rank[1] = right;
    FreeSolve other{free.stadium_only};
    std::optional<Silhouette> t = AtSilhouette(w, center, scale, pooled, start_place, &other);
    if (t && top.Over(*t) <= kTopOffNoise && (!out.other || t->residual_variance < out.other->residual_variance))
      out.other = t;
  }
  return out;
}

double SilhouetteVariance(const Silhouette& s, const PooledShape* held, const double gradient[4], double by_exponent) {
  // Each end from one side of its cell to the other: the area seen changes
  // by the wall times the step (less where the left end moves in, more where
  // the right one moves out), the groove as the ellipse re-solved there
  // (linear in the step: z0 and b by their derivatives in the end's place).
  // (Placing anew the bead each such ellipse would show, its seen area's
  // trapezoids against their integral, gave the same: 0.0099 mm^2 against
  // 0.0096 on part/silhouette_test.cc's beads.)
  double ends = 0.0;
  for (int side = 0; side < 2; ++side) {
    const double step = s.cell[2 * side + 1] - s.cell[2 * side];
    Ellipse moved = s.e;
    moved.x0 += 0.5 * step, moved.a += (side ? 0.5 : -0.5) * step;
    moved.z0 += s.z0_by_end[side] * step, moved.b += s.b_by_end[side] * step;
    // (A tamped bead held at its half-height, PooledShape::held_b_mm, is
    // moved here as its aspect held would be, b with a: moved with b held,
    // the ends' term of a generator's tamped walls under a footprint fell
    // by a quarter and their intervals covered 89-94 % (their upper layers
    // 70-91 %), their errors holding more than the ends' places (the surface
    // below's cliffs read through the spots), which the model does not
    // hold.)
    // The area seen across the wall's cell is the bead placed's
    // (CellSeenChange), so it moves with the place as the groove does, a
    // mixed end's too. (Left to follow the end where the profiler averages
    // over a footprint, as the spots' integral across the cell would, after
    // that area was the placed bead's: a generator's tamped walls' beads on
    // the bed were corrected to 0.024 mm^2 at sigmas of 0.015, 75 % covered.)
    const double seen = (side ? s.wall_right : -s.wall_left) * step;
    const double range = GrooveChange(s.e, moved, gradient) - seen;
    // About the end's place: the end anywhere in its cell alike, placed off
    // its middle by d (by the top: PlaceByTop), its error's mean square
    // cell^2 / 12 + d^2. (The top's place is not counted as knowledge: a held
    // shape a little off the tops, as where a quarter of a twin's layer's
    // tops carry a bump the pool took in, places an end up to its cell off,
    // and the others' intervals covered 88 % for 98 %.)
    const double placed = side ? s.e.x0 + s.e.a : s.e.x0 - s.e.a;
    const double off = step > 0.0 ? (placed - 0.5 * (s.cell[2 * side] + s.cell[2 * side + 1])) / step : 0.0;
    ends += range * range * (1.0 / 12.0 + off * off);
  }
  // z0 and b to their covariance.
  const double g_z0 = gradient[1], g_b = gradient[3];
  const double solved =
      s.residual_variance * (g_z0 * g_z0 * s.z0_var + 2.0 * g_z0 * g_b * s.z0_b + g_b * g_b * s.b_var);
  if (!held) return ends + solved;
  // A held aspect a sigma off: b moves by a sigma, z0 by the mean of s
  // times that, the other way. A held exponent a sigma off: the groove by
  // its own derivative, z0 re-solved (the area seen stays: the ends do).
  // (A tamped bead's b held: its half-height's sigma.)
  const double by_b = g_b - g_z0 * s.mean_s;
  const double by_aspect =
      std::isfinite(held->held_b_mm) ? by_b * held->half_height_sigma_mm : by_b * s.e.a * held->aspect_sigma;
  const double by_p = (by_exponent + g_z0 * s.z0_by_exponent) * held->exponent_sigma;
  return ends + solved + by_aspect * by_aspect + by_p * by_p + 2.0 * held->correlation * by_aspect * by_p;
}

}  // namespace bead::part
