// The superellipse a wall's bead is taken to be (part/superellipse.h): its
// half height, its derivatives, and their table.
#include "libbead/part/superellipse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "libbead/part/part_kernel.h"
#include "libbead/part/superellipse_sums.h"

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

// The stadium (p = -c): flat over |u| <= 1 - c, a quarter ellipse of
// semi-axes c a and b at each end; c = 1 is the ellipse again.
TEST(Superellipse, AStadiumIsAFlatTopWithQuarterEllipseEnds) {
  for (double u : {-0.95, -0.5, 0.0, 0.3, 0.8}) {
    const SuperellipseTable::Value v = SuperellipseAt(u, -1.0);
    EXPECT_NEAR(v.s, std::sqrt(1.0 - u * u), 1e-14) << u;
    EXPECT_NEAR(v.ds_du, -u / std::sqrt(1.0 - u * u), 1e-12) << u;
  }
  const double c = 0.3;
  for (double u : {-0.69, 0.0, 0.5, 0.7}) EXPECT_EQ(SuperellipseS(u, -c), 1.0) << u;
  for (double u : {0.75, -0.85, 0.99}) {
    const double w = (std::abs(u) - (1.0 - c)) / c;
    EXPECT_NEAR(SuperellipseS(u, -c), std::sqrt(1.0 - w * w), 1e-14) << u;
  }
  EXPECT_TRUE(IsStadium(-c));
  EXPECT_FALSE(IsStadium(2.0));
}

// Its derivatives in u and in p are the central differences' too (away
// from the flat top's end, where s' jumps from 0 to the arc's), and
// ReachAt inverts s in either family.
TEST(Superellipse, AStadiumsDerivativesAreTheDifferencesAndReachInvertsIt) {
  const double h = 1e-5;
  for (double p : {-0.2, -0.45, -0.9, -1.3})
    for (double u : {-0.95, -0.85, 0.1, 0.6, 0.9}) {
      if (std::abs(std::abs(u) - (1.0 + p)) < 0.05) continue;
      const SuperellipseTable::Value v = SuperellipseAt(u, p);
      const double by_u = (SuperellipseAt(u + h, p).s - SuperellipseAt(u - h, p).s) / (2 * h);
      const double by_p = (SuperellipseAt(u, p + h).s - SuperellipseAt(u, p - h).s) / (2 * h);
      EXPECT_NEAR(v.ds_du, by_u, 1e-6) << p << " " << u;
      EXPECT_NEAR(v.ds_dp, by_p, 1e-6) << p << " " << u;
    }
  for (double p : {-0.3, -1.0, 1.5, 2.0, 4.0})
    for (double share : {0.1, 0.5, 0.9}) EXPECT_NEAR(SuperellipseS(ReachAt(share, p), p), share, 1e-9) << p;
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

// A window over a bead on a sloping surface below (points 0.05 mm apart,
// the top seen where it stands over the surface).
Window BeadWindow(const Ellipse& bead) {
  Window w;
  for (double x = -5.0; x <= 5.0; x += 0.05) {
    const double old = 0.1 * x + 0.2;
    w.x.push_back(x), w.old.push_back(old);
    w.z.push_back(std::max(old, bead.z0 + bead.Half(x)) + 0.01 * std::sin(37.0 * x));
  }
  return w;
}

// A fit's sums at p = 2 are the kernel's ellipse's (the table holds s to
// 6e-6 of b; the slope is held at 50 where the kernel holds s at 0.02:
// the same but within 2e-4 of u of the ends), with the aspect free and held.
TEST(Superellipse, AFitsSumsAtTwoAreTheKernelsEllipse) {
  const Ellipse bead{0.2, 0.5, 3.0, 1.5, 2.0}, at{0.25, 0.45, 2.9, 1.55, 2.0};
  const Window w = BeadWindow(bead);
  for (double aspect : {std::nan(""), 0.5}) {
    const EllipseSums mine = SuperellipseSums(w, 0, w.x.size(), at, aspect);
    const EllipseSums kernel = ActivePartKernel().ellipse(w.x.data(), w.z.data(), w.old.data(), 0, w.x.size(),
                                                          {at.x0, at.z0, at.a, at.b, aspect});
    EXPECT_NEAR(mine.rss, kernel.rss, 1e-4 * kernel.rss) << aspect;
    for (int k = 0; k < 10; ++k) EXPECT_NEAR(mine.jtj[k], kernel.jtj[k], 1e-4 * (1.0 + std::abs(kernel.jtj[k]))) << k;
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(mine.jtr[k], kernel.jtr[k], 1e-4 * (1.0 + std::abs(kernel.jtr[k]))) << k;
  }
}

// At another exponent, J^T r is half the gradient of the residuals' sum of
// squares: the central differences' in x0, z0, a and b (h = 1e-6 mm; the
// points where the top meets the surface below, a kink, move by less; the
// ends, where the side drops to the surface below, lie off the points).
TEST(Superellipse, AFitsSumsAreTheResidualsGradient) {
  const Ellipse bead{0.2, 0.5, 3.0, 1.4, 2.6}, at{0.3137, 0.42, 2.8512, 1.5, 2.6};
  const Window w = BeadWindow(bead);
  const EllipseSums sums = SuperellipseSums(w, 0, w.x.size(), at, NAN);
  const double h = 1e-6;
  for (std::size_t i = 0; i < 4; ++i) {
    Ellipse up = at, down = at;
    up[i] += h, down[i] -= h;
    const double by_i =
        (SuperellipseSums(w, 0, w.x.size(), up, NAN).rss - SuperellipseSums(w, 0, w.x.size(), down, NAN).rss) / (4 * h);
    EXPECT_NEAR(sums.jtr[i], by_i, 1e-3 * (1.0 + std::abs(by_i))) << i;
  }
}

}  // namespace
}  // namespace bead::part
