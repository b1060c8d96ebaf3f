// The top's least squares, shared by the solves with the shape held
// (part/silhouette_top.cc) and free (part/free_top.cc): the top's points of
// a bead with its ends placed, their sums at an exponent, and z0 and b
// solved from them (part/silhouette_top.h says what is solved).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "libbead/part/groove_window.h"
#include "libbead/part/silhouette.h"
#include "libbead/part/superellipse.h"

namespace bead::part {

// The top's points within 0.9 of the half-width of the bead with ends L
// and R (SuperellipseTable::kTabulatedU: where the tables hold s): u, z,
// and where u falls in the exponents' tables (the same in all).
struct TopPoints {
  double per_a = 0.0;
  std::vector<double> u, z, t;
  std::vector<int> k;
};

const TopPoints& TopOf(const Window& w, std::size_t first, std::size_t last, double L, double R);

// The least squares' sums over the top's points at exponent t: of 1, s,
// s^2, z, z s, z^2 and ds/dp, and the derivatives of s, s^2 and z s in x0
// and a (through u = (x - x0) / a: ds/dx0 = -s'(u) / a, ds/da = u
// ds/dx0).
struct TopSums {
  double m = 0, s1 = 0, s2 = 0, z1 = 0, zs = 0, zz = 0, sp = 0;
  double d1[2] = {}, d2[2] = {}, dz[2] = {};
};

TopSums SumTop(const TopPoints& p, const SuperellipseTable& t);
// SumTop(TopOf(w, first, last, L, R), table)'s sums of 1, s, s^2, z, z s
// and z^2 alone (not ds/dp nor the derivatives), four points a register
// (part/part_kernel.h) without the points written out; nothing (m = 0)
// where R is not right of L.
TopSums TableSums(const Window& w, std::size_t first, std::size_t last, double L, double R,
                  const SuperellipseTable& table);
// The same over the points [lo, hi) given (part/silhouette_top.h: TopRange).
TopSums TableSumsOver(const Window& w, std::pair<std::size_t, std::size_t> range, double L, double R,
                      const SuperellipseTable& table);

// The free solve from the sums: its residual variance (INFINITY where b
// is not positive or too few points are), z0 and b.
struct FreeTop {
  double rss = INFINITY, z0 = NAN, b = NAN;
};
FreeTop FreeResidual(const TopSums& t);

// z0 and b (b = aspect a where held) from the sums, for the bead with ends L
// and R, and their derivatives in each end's place (the points kept: x0 and
// a each moving by half an end's step); false where too few points are, or
// b is not positive.
bool SolveTop(const TopSums& t, double L, double R, double aspect, Silhouette& s);

}  // namespace bead::part
