// The superellipse a wall's bead is taken to be (part/superellipse.h): its
// half height, its derivatives, and their table.
#include "libbead/part/superellipse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

namespace bead::part {
namespace {

// p = 2 is the ellipse: s = sqrt(1 - u^2), ds/du = -u / s.
TEST(Superellipse, TwoIsTheEllipse) {
  for (double u : {-0.95, -0.5, 0.0, 0.3, 0.8}) {
    const SuperellipseTable::Value v = SuperellipseAt(u, 2.0);
    EXPECT_NEAR(v.s, std::sqrt(1.0 - u * u), 1e-14) << u;
    EXPECT_NEAR(v.ds_du, -u / std::sqrt(1.0 - u * u), 1e-12) << u;
  }
}

// The derivatives in u and in p are the central differences' of s, to the
// differences' own truncation (h^2 times the third derivative: 1e-6 here).
TEST(Superellipse, TheDerivativesAreTheDifferences) {
  const double h = 1e-5;
  for (double p : {1.3, 2.0, 2.7, 5.0})
    for (double u : {-0.85, -0.2, 0.1, 0.6, 0.9}) {
      const SuperellipseTable::Value v = SuperellipseAt(u, p);
      const double by_u = (SuperellipseAt(u + h, p).s - SuperellipseAt(u - h, p).s) / (2 * h);
      const double by_p = (SuperellipseAt(u, p + h).s - SuperellipseAt(u, p - h).s) / (2 * h);
      EXPECT_NEAR(v.ds_du, by_u, 1e-6) << p << " " << u;
      EXPECT_NEAR(v.ds_dp, by_p, 1e-6) << p << " " << u;
    }
}

// The table, linear between its entries (|u| steps of 0.9 / 512), holds s
// to the interpolation's bound, the step squared over 8 times |s''|, for
// the ellipse (|s''| <= 12 up to u = 0.9) and p = 3.5 (16); below p = 2
// s'' is unbounded at u = 0, where s - 1 ~ -|u|^p / p: over the first step,
// 0.2 of 0.0018^1.3 / 1.3 at p = 1.3, ~3e-5. It is exact at the groove's nodes.
TEST(Superellipse, TheTableHoldsTheValuesBetweenItsEntries) {
  const double h = 0.9 / 512;
  for (auto [p, bound] : {std::pair{1.3, 3e-5}, std::pair{2.0, 12 * h * h / 8}, std::pair{3.5, 16 * h * h / 8}}) {
    const SuperellipseTable& t = SuperellipseOf(p);
    for (double u = -0.9; u <= 0.9; u += 0.0003) EXPECT_NEAR(t.At(u).s, SuperellipseAt(u, p).s, bound) << p << " " << u;
    for (int k = 0; k < SuperellipseTable::kNodes; ++k)
      EXPECT_DOUBLE_EQ(t.node_s()[k], SuperellipseAt(t.node_u()[k], p).s) << p << " " << k;
  }
}

// A part of many layers pools as many exponents, each its own table; the
// grid's tables stay while they come and go (a free solve holds five of
// them at once: one let go under it was read after it was freed).
TEST(Superellipse, TheGridsTablesOutliveManyLayersExponents) {
  const std::vector<double>& grid = SuperellipseGrid();
  const SuperellipseTable& first = SuperellipseOf(grid.front());
  const SuperellipseTable& last = SuperellipseOf(grid.back());
  for (int layer = 0; layer < 100; ++layer) SuperellipseOf(1.95 + 0.001 * layer);
  EXPECT_EQ(&SuperellipseOf(grid.front()), &first);
  EXPECT_EQ(&SuperellipseOf(grid.back()), &last);
  EXPECT_EQ(first.p(), grid.front());
  EXPECT_EQ(last.p(), grid.back());
}

}  // namespace
}  // namespace bead::part
