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

#include <cstddef>

#include "libbead/part/groove_window.h"
#include "libbead/part/silhouette.h"

namespace bead::part {

// The top with the shape held, its ends at L and R (the window's points
// first..last the bead's): z0, b = aspect a (or b solved where the aspect
// is NaN), their covariance and derivatives in the ends' places.
bool SolveHeld(const Window& w, std::size_t first, std::size_t last, double L, double R, const PooledShape& held,
               Silhouette& s);

// The top with the shape free: from grid index `from` downhill to the least
// residual, the exponent, z0 and b interpolated between the grid's around it.
// Returns the least's grid index (-1: none solved).
std::ptrdiff_t SolveFree(const Window& w, std::size_t first, std::size_t last, double L, double R, Silhouette& s,
                         std::ptrdiff_t from);

// The grid index nearest the ellipse's exponent, where a free search starts.
std::ptrdiff_t EllipseIndex();

// How many of the window's points the top is solved over.
std::size_t TopPointCount(const Window& w, std::size_t first, std::size_t last, double L, double R);

// The free shape s (solved at ends L, R, grid index `found`) with its ends
// placed within their cells by the top: s's aspect, exponent, their
// variances from the ends' places and from the grid's steps, and whether
// the top agrees with the cells (Silhouette::shape_consistent); the
// placement starts from `start` (Silhouette::end_place: the row before's)
// where given, else from the cells' middles.
void ShapeByTop(const Window& w, std::size_t first, std::size_t last, double L, double R, std::ptrdiff_t found,
                Silhouette& s, const double* start = nullptr);

}  // namespace bead::part
