// The top of a bead placed at its silhouette, solved (part/silhouette.h):
// with its ends placed, the top's height z0 + b s(u) over the points within
// 0.9 of the half-width is linear in z0 and b (z0 alone with the aspect held),
// solved by least squares; the exponent, where it is not held, is the one of
// SuperellipseGrid whose solution leaves the least residual, refined between
// its neighbours.
//
// For a layer's pool the free shape's ends are then placed within their
// cells by the top itself (ShapeByTop): placed at the cells' middles, a row's
// aspect is off by up to what half a cell moves it, and where the rows'
// widths sweep under a cell (a coarse profiler, a steady bead) those errors
// do not average out over the pool.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "libbead/part/groove_window.h"
#include "libbead/part/silhouette.h"

namespace bead::part {

// The top with the shape held, its ends at L and R (the window's points
// first..last the bead's): z0, b = aspect a (or b solved where the aspect
// is NaN), their covariance and derivatives in the ends' places.
bool SolveHeld(const Window& w, std::size_t first, std::size_t last, double L, double R, const PooledShape& held,
               Silhouette& s);
// What SolveHeld leaves of the top alone, where the aspect is held: its
// residual variance (INFINITY where it does not solve) over `points` points:
// the top's within 0.9 of the half-width, or those of `range` where given.
double HeldTopVariance(const Window& w, std::size_t first, std::size_t last, double L, double R,
                       const PooledShape& held, std::size_t& points,
                       const std::pair<std::size_t, std::size_t>* range = nullptr);
// The top's points within 0.9 of the half-width of the bead with ends L and
// R > L (SuperellipseTable::kTabulatedU: where the tables hold s): [lo, hi)
// of first .. last (x increases, and u with it: one range).
std::pair<std::size_t, std::size_t> TopRange(const Window& w, std::size_t first, std::size_t last, double L, double R);

// Where the held top places the end `side` (0 left, 1 right) of the bead
// with ends L and R within its cell [s.cell[2 side], s.cell[2 side + 1]]:
// its residual searched over the cell a quarter spacing at a time, the
// least refined by the parabola through it and its neighbours, `at` in mm
// (within the cell) with the variance the residual's curvature gives it
// (INFINITY where the least has no neighbour either side, or the residual
// is not curved upward there); nullopt where no place solves.
// same_points: the top read over the same points at every place (those
// within 0.9 of the half-width with the end at the cell's inner edge), and
// a least at the cell's first or last place refined too, by the parabola
// through the three places nearest that edge (part/silhouette.cc:
// PlaceByTop says where).
struct TopPlace {
  double at = 0.0, sigma2 = INFINITY;
};
std::optional<TopPlace> SearchCell(const Window& w, std::size_t first, std::size_t last, double spacing,
                                   const PooledShape& held, int side, bool same_points, double L, double R,
                                   const Silhouette& s);

// The outermost points of a top (first..last) that stand under its z0 by
// more than three residual sigmas (sigma_mm) are not on it: no point of a
// top lies under its widest point. Such a point is a mix of the top's end
// and the wall's foot (a profiler averaging over its spot or pixel), or the
// layer below's wall beside the end, its gain risen by the surface below
// interpolated a fraction of a spacing off (so the largest rise was not
// the bead's end). The end then lies anywhere from its wall's cell to the
// first point inward that is on the top: that side's cell (cell[1] left,
// cell[2] right; not where gapped) is widened inward to it. The cell's
// outer point (first - 1, last + 1) standing over the surface below by
// more than three sigmas is a mix too, of the wall's foot and an end that
// may lie beyond it: the cell is widened outward to the point past it.
// Returns the outermost points on the top (first, last where they are, or
// where no point of its half of the top is).
// (On a generator's wall of pressed ellipses whose points average over a
// spot as wide as their spacing, the layers' pooled aspects were
// 0.495-0.498 for 0.500, now 0.497-0.501. With points that do not
// average, 1-14 % of the rows of layers 2-6 had an end outside its cell,
// their intervals covering 47-86 % of them: now widened to where the top
// is.)
// mixed (where given): whether each side's cell was widened.
std::pair<std::size_t, std::size_t> OnTheTop(const Window& w, std::size_t first, std::size_t last, double z0,
                                             double sigma_mm, const bool gapped[2], double cell[4],
                                             bool* mixed = nullptr);

// The top with the shape free over a family's grid (part/superellipse.h:
// SuperellipseGrid or StadiumGrid): from grid index `from` downhill to the
// least residual, the exponent, z0 and b interpolated between the grid's
// around it. Returns the least's grid index (-1: none solved); variance
// (where given): the top's residual variance at the least (between the
// grid's exponents, where it is interpolated).
std::ptrdiff_t SolveFree(const Window& w, std::size_t first, std::size_t last, double L, double R, Silhouette& s,
                         std::ptrdiff_t from, const std::vector<double>& grid, double* variance = nullptr);

// The grid index nearest the ellipse, where a free search starts.
std::ptrdiff_t EllipseIndex(const std::vector<double>& grid);

// How many of the window's points the top is solved over.
std::size_t TopPointCount(const Window& w, std::size_t first, std::size_t last, double L, double R);

// The free shape s (solved at ends L, R, grid index `found`) with its ends
// placed within their cells by the top: s's aspect, exponent, their
// variances from the ends' places and from the grid's steps, and whether
// the top agrees with the cells (Silhouette::shape_consistent); the
// placement starts from `start` (Silhouette::end_place: the row before's)
// where given, else from the cells' middles.
void ShapeByTop(const Window& w, std::size_t first, std::size_t last, double L, double R, std::ptrdiff_t found,
                const std::vector<double>& grid, Silhouette& s, const double* start = nullptr);

}  // namespace bead::part
