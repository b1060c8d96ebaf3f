// The top with the shape free (part/silhouette_top.h: SolveFree,
// ShapeByTop): solved at the exponents of SuperellipseGrid around the least
// residual and between them, and for a layer's pool its ends placed within
// their cells by the top itself.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "libbead/part/silhouette_top.h"
#include "libbead/part/superellipse.h"
#include "libbead/part/top_sums.h"

namespace bead::part {
namespace {

// The top solved free between the grid's exponents around the least, grid
// index k: from the solves at k - 1, k, k + 1 (f[0..2]), the vertex of the
// parabola through their residuals in ln p (x grid steps from k) and z0 and
// b there by Lagrange's interpolation; with `beyond`, the solve at k + 2
// side (side the vertex's), the cubic's (Newton's form: the parabola plus
// the third divided difference times (x + 1) x (x - 1)), its vertex by a
// Newton step from the parabola's, and (dx, db) the cubic's less the
// parabola's: the grid's own error, to the next order. false where the
// residual is not curved upward there.
struct Between {
  double x = 0.0, z0 = NAN, b = NAN;
  double dx = 0.0, db = 0.0;
};
bool Interpolate(const FreeTop f[3], const FreeTop* beyond, int side, Between& out) {
  const double curve = f[0].rss - 2.0 * f[1].rss + f[2].rss;
  if (!std::isfinite(curve) || !(curve > 0.0)) return false;
  const auto parabola = [&](double FreeTop::*v, double x) {
    return f[0].*v * 0.5 * x * (x - 1.0) + f[1].*v * (1.0 - x * x) + f[2].*v * 0.5 * x * (x + 1.0);
  };
  const double t = std::clamp(0.5 * (f[0].rss - f[2].rss) / curve, -1.0, 1.0);
  out = {t, parabola(&FreeTop::z0, t), parabola(&FreeTop::b, t)};
  if (!beyond || !std::isfinite(beyond->rss)) return true;
  const FreeTop &near = f[1 + side], &far = f[1 - side];
  const auto third = [&](double FreeTop::*v) {
    return side * (beyond->*v - 3.0 * (near.*v) + 3.0 * (f[1].*v) - far.*v) / 6.0;
  };
  const auto term = [](double x) { return (x + 1.0) * x * (x - 1.0); };
  const double k = third(&FreeTop::rss), slope = curve + 6.0 * k * t;
  const double x = slope > 0.0 ? std::clamp(t - k * (3.0 * t * t - 1.0) / slope, -1.0, 1.0) : t;
  const Between cubic{x, parabola(&FreeTop::z0, x) + third(&FreeTop::z0) * term(x),
                      parabola(&FreeTop::b, x) + third(&FreeTop::b) * term(x)};
  out = cubic;
  out.dx = x - t, out.db = cubic.b - parabola(&FreeTop::b, t);
  return true;
}

// The free solves at the grid's exponents k - 2 .. k + 2 (the top's points
// of the bead with ends L and R).
std::array<FreeTop, 5> FiveSolves(const Window& w, std::size_t first, std::size_t last, double L, double R,
                                  std::size_t k, const std::vector<double>& grid) {
  std::array<FreeTop, 5> out;
  for (std::size_t i = 0; i < 5; ++i)
    out[i] = FreeResidual(TableSums(w, first, last, L, R, SuperellipseOf(grid[k + i - 2])));
  return out;
}

// The top solved free at each exponent of the grid around the least (from
// grid index `found`): z0, b and the exponent between the grid's to the
// next order (Interpolate), the residual variance at the least, the aspect,
// and what the grid's steps leave in the aspect and exponent (the cubic's
// less the parabola's). The least is moved along the grid where the vertex
// lies nearer a neighbour. false where the grid ends or nothing is solved.
struct FreeShape {
  double z0 = NAN, b = NAN, exponent = NAN, residual_variance = NAN, aspect = NAN;
  double aspect_grid_var = 0.0, exponent_grid_var = 0.0;
};
bool ShapeBetween(const Window& w, std::size_t first, std::size_t last, double L, double R,
                  const std::vector<double>& grid, std::ptrdiff_t& found, FreeShape& out) {
  for (int moves = 0; moves < 3; ++moves) {
    if (found < 2 || found + 2 >= std::ssize(grid)) return false;
    const auto k = static_cast<std::size_t>(found);
    const std::array<FreeTop, 5> f5 = FiveSolves(w, first, last, L, R, k, grid);
    const FreeTop f[3] = {f5[1], f5[2], f5[3]};
    Between there;
    if (!Interpolate(f, nullptr, 0, there)) return false;
    const int side = there.x >= 0.0 ? 1 : -1;
    if (std::abs(there.x) > 0.5 && moves < 2) {
      found += side;
      continue;
    }
    if (!Interpolate(f, &f5[static_cast<std::size_t>(2 + 2 * side)], side, there)) return false;
    const double a = 0.5 * (R - L), step = std::log(grid[k + 1] / grid[k]);
    out.z0 = there.z0, out.b = there.b, out.exponent = grid[k] * std::exp(there.x * step);
    out.residual_variance = f[1].rss, out.aspect = there.b / a;
    const double da = there.db / a, dp = out.exponent * there.dx * step;
    out.aspect_grid_var = da * da, out.exponent_grid_var = dp * dp;
    return std::isfinite(out.aspect) && out.b > 0.0;
  }
  return false;
}

// Where the top f places the ends: the outermost point of the top on each
// side stands a share h = (z - z0) / b of its half-height up, at |u| =
// ReachAt(h) of the half-width from the centre; the two points' places give
// x0 and a, the ends x0 -+ a, held to their cells. Each end's sigma: half
// the range its point's height one residual sigma either way moves it over
// (at most the cell's uniform sigma, half / sqrt 3); consistent: each end
// lies in its cell to three of those sigmas.
struct EndsPlaced {
  double end[2] = {}, sigma[2] = {};
  bool consistent = true;
};
EndsPlaced PlaceEnds(const Window& w, std::size_t first, std::size_t last, const double cell[4], const FreeShape& f) {
  const double sigma_h = std::sqrt(f.residual_variance) / f.b;
  const double h[2] = {(w.z[first] - f.z0) / f.b, (w.z[last] - f.z0) / f.b};
  const double reach[2] = {ReachAt(h[0], f.exponent), ReachAt(h[1], f.exponent)};
  const double a = (w.x[last] - w.x[first]) / (reach[0] + reach[1]);
  const double x0 = w.x[first] + a * reach[0];
  EndsPlaced out;
  for (int side = 0; side < 2; ++side) {
    const double lo = cell[2 * side], hi = cell[2 * side + 1], end = side ? x0 + a : x0 - a;
    out.end[side] = std::clamp(end, lo, hi);
    const double range =
        0.5 * a * std::abs(ReachAt(h[side] - sigma_h, f.exponent) - ReachAt(h[side] + sigma_h, f.exponent));
    out.sigma[side] = std::min(range, 0.5 * (hi - lo) / std::sqrt(3.0));
    out.consistent = out.consistent && std::abs(end - out.end[side]) <= 3.0 * range + 1e-3 * (hi - lo);
  }
  return out;
}

// The ends placed by the top and the top solved again there, until neither
// end moves by a hundredth of its cell (at most kPlacements times).
constexpr int kPlacements = 8;
constexpr double kSettledCell = 1e-2;

}  // namespace

// The shape free: solved at the exponents of the grid, from grid index
// `from` downhill to the least residual (the residual changes smoothly with
// the exponent: one least), its exponent, z0 and b between the grid's
// (Interpolate's parabola).
std::ptrdiff_t SolveFree(const Window& w, std::size_t first, std::size_t last, double L, double R, Silhouette& s,
                         std::ptrdiff_t from, const std::vector<double>& grid, double* variance) {
  const auto n = static_cast<std::ptrdiff_t>(grid.size());
  std::vector<FreeTop> solved(grid.size(), FreeTop{NAN});
  // The solve at grid index k (its residual INFINITY off the grid or unsolved).
  const auto at = [&](std::ptrdiff_t k) -> const FreeTop& {
    static const FreeTop none;
    if (k < 0 || k >= n) return none;
    const auto i = static_cast<std::size_t>(k);
    if (std::isnan(solved[i].rss)) solved[i] = FreeResidual(TableSums(w, first, last, L, R, SuperellipseOf(grid[i])));
    return solved[i];
  };
  std::ptrdiff_t best = std::clamp<std::ptrdiff_t>(from, 0, n - 1);
  const std::ptrdiff_t way = at(best + 1).rss < at(best).rss ? 1 : -1;
  while (at(best + way).rss < at(best).rss) best += way;
  const auto b = static_cast<std::size_t>(best);
  if (!std::isfinite(at(best).rss) ||
      !SolveTop(SumTop(TopOf(w, first, last, L, R), SuperellipseOf(grid[b])), L, R, NAN, s))
    return -1;
  const double a = 0.5 * (R - L);
  s.e.p = s.exponent = grid[b], s.aspect = solved[b].b / a;
  if (variance) *variance = solved[b].rss;
  const FreeTop around[3] = {at(best - 1), solved[b], at(best + 1)};
  Between there;
  if (!Interpolate(around, nullptr, 0, there)) return best;
  s.exponent = grid[b] * std::pow(grid[b + 1] / grid[b], there.x);
  s.aspect = there.b / a;
  // The residual at the vertex, the parabola's there (the least between
  // the grid's exponents: two families are compared at their leasts).
  const double x = there.x;
  if (variance)
    *variance =
        around[0].rss * 0.5 * x * (x - 1.0) + around[1].rss * (1.0 - x * x) + around[2].rss * 0.5 * x * (x + 1.0);
  return best;
}

// The grid index nearest the ellipse, where a free search starts.
std::ptrdiff_t EllipseIndex(const std::vector<double>& grid) {
  const double ellipse = EllipseOf(grid.front());
  std::ptrdiff_t k = 0;
  while (k + 1 < std::ssize(grid) && std::abs(grid[static_cast<std::size_t>(k) + 1] - ellipse) <
                                         std::abs(grid[static_cast<std::size_t>(k)] - ellipse))
    ++k;
  return k;
}

namespace {

// What the free shape owes to where its ends lie: solved again (solve(l,
// r, aspect, exponent)) with each end moved by half its cell, the aspect's
// and exponent's changes over that step times the end's sigma; and times
// the width its mixed points widened the cell by over sqrt 12 (mixed[side]:
// 0 where none; part/silhouette.h: Silhouette::aspect_mixed_var).
template <class Solve>
void EndsVariance(const double ends[2], const double sigma[2], const double mixed[2], double aspect, double exponent,
                  Solve solve, Silhouette& s) {
  s.aspect_end_var = s.exponent_end_var = s.aspect_mixed_var = s.exponent_mixed_var = 0.0;
  for (int side = 0; side < 2; ++side) {
    const double half = 0.5 * (s.cell[2 * side + 1] - s.cell[2 * side]);
    double moved[2] = {ends[0], ends[1]}, moved_aspect = NAN, moved_exponent = NAN;
    moved[side] += half;
    if (!solve(moved[0], moved[1], moved_aspect, moved_exponent)) continue;
    const double da = (moved_aspect - aspect) / half, dp = (moved_exponent - exponent) / half;
    const double v = sigma[side] * sigma[side];
    s.aspect_end_var += da * da * v, s.exponent_end_var += dp * dp * v;
    const double spot = mixed[side] * mixed[side] / 12.0;
    s.aspect_mixed_var += da * da * spot, s.exponent_mixed_var += dp * dp * spot;
  }
}

// Where the exponent lies at the grid's ends (no two grid exponents beyond
// it either way), the ends stay at their cells' middles, each anywhere in
// its cell (uniform: sigma half / sqrt 3).
void EndsAnywhereInTheirCells(const Window& w, std::size_t first, std::size_t last, double L, double R,
                              std::ptrdiff_t from, const std::vector<double>& grid, Silhouette& s) {
  const double ends[2] = {L, R}, unmixed[2] = {0.0, 0.0};
  s.shape_a = 0.5 * (R - L);
  const double sigma[2] = {0.5 * (s.cell[1] - s.cell[0]) / std::sqrt(3.0),
                           0.5 * (s.cell[3] - s.cell[2]) / std::sqrt(3.0)};
  EndsVariance(
      ends, sigma, unmixed, s.aspect, s.exponent,
      [&](double l, double r, double& aspect, double& exponent) {
        Silhouette moved = s;
        if (SolveFree(w, first, last, l, r, moved, from, grid) < 0) return false;
        aspect = moved.aspect, exponent = moved.exponent;
        return true;
      },
      s);
}

}  // namespace

// Placed at the cells' middles, the ends left a layer's pooled aspect 2-4 %
// off on an independent contour at 0.1 mm spacing (the rows' widths sweeping
// under a cell, the phases' errors not averaging out); the top between the
// grid's exponents interpolated by the parabola alone, -1.7 % on noise-free
// ellipses (the cubic: under 0.1 %).
void ShapeByTop(const Window& w, std::size_t first, std::size_t last, double L, double R, std::ptrdiff_t found,
                const std::vector<double>& grid, Silhouette& s, const double* start) {
  FreeShape f;
  double ends[2] = {L, R};
  const auto in_cell = [&](int side, double place) {
    return s.cell[2 * side] + place * (s.cell[2 * side + 1] - s.cell[2 * side]);
  };
  // From where the row before's ends settled in their cells (a bead's
  // width changes little from one profile to the next), else the middles.
  bool solved = false;
  if (start && std::isfinite(start[0]) && std::isfinite(start[1])) {
    std::ptrdiff_t at = found;
    const double warm[2] = {in_cell(0, start[0]), in_cell(1, start[1])};
    if ((solved = ShapeBetween(w, first, last, warm[0], warm[1], grid, at, f)))
      ends[0] = warm[0], ends[1] = warm[1], found = at;
  }
  if (!solved && !ShapeBetween(w, first, last, L, R, grid, found, f))
    return EndsAnywhereInTheirCells(w, first, last, L, R, found, grid, s);
  // Each end placed from the outermost point on the top (OnTheTop: one
  // under its z0 is a mix of the end and the wall's foot, or another wall).
  constexpr bool kNoGaps[2] = {false, false};
  const double wall_cell[2] = {s.cell[1] - s.cell[0], s.cell[3] - s.cell[2]};
  const auto [top_first, top_last] =
      OnTheTop(w, first, last, f.z0, std::sqrt(f.residual_variance), kNoGaps, s.cell, s.end_mixed);
  // What the mixed points widened each cell by: the spot's reach there.
  const double mixed[2] = {s.cell[1] - s.cell[0] - wall_cell[0], s.cell[3] - s.cell[2] - wall_cell[1]};
  EndsPlaced placed = PlaceEnds(w, top_first, top_last, s.cell, f);
  for (int k = 0; k < kPlacements; ++k) {
    const double moved = std::max(std::abs(placed.end[0] - ends[0]) / (s.cell[1] - s.cell[0]),
                                  std::abs(placed.end[1] - ends[1]) / (s.cell[3] - s.cell[2]));
    if (moved < kSettledCell) break;
    FreeShape there;
    if (!ShapeBetween(w, first, last, placed.end[0], placed.end[1], grid, found, there)) break;
    ends[0] = placed.end[0], ends[1] = placed.end[1], f = there;
    placed = PlaceEnds(w, top_first, top_last, s.cell, f);
  }
  for (int side = 0; side < 2; ++side)
    s.end_place[side] = (ends[side] - s.cell[2 * side]) / (s.cell[2 * side + 1] - s.cell[2 * side]);
  s.aspect = f.aspect, s.exponent = f.exponent, s.shape_a = 0.5 * (ends[1] - ends[0]);
  s.aspect_grid_var = f.aspect_grid_var, s.exponent_grid_var = f.exponent_grid_var;
  s.end_sigma[0] = placed.sigma[0], s.end_sigma[1] = placed.sigma[1];
  s.shape_consistent = placed.consistent;
  EndsVariance(
      ends, placed.sigma, mixed, f.aspect, f.exponent,
      [&](double l, double r, double& aspect, double& exponent) {
        std::ptrdiff_t at = found;
        FreeShape m;
        if (!ShapeBetween(w, first, last, l, r, grid, at, m)) return false;
        aspect = m.aspect, exponent = m.exponent;
        return true;
      },
      s);
}

}  // namespace bead::part
