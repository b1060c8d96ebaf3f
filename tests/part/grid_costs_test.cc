// The registration's costs eight points at a time (part/grid_costs.h)
// against their definition written point by point (SurfaceRow::SampleAt),
// over a layer below with a gap and bridged values, new points off the
// grid's phase with dropouts, at shifts that fall anywhere between two
// grid values.
#include "libbead/part/grid_costs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace bead::part {
namespace {

constexpr double kGridDx = 0.05, kNoise = 0.01, kTau = 0.06;

double LowerBead(double x) { return std::abs(x) < 4.0 ? 1.5 * std::sqrt(1.0 - x * x / 16.0) : 0.0; }

// The layer below on its points' grid: a gap of 0.3 mm not seen, a
// stretch bridged (variance under one point's; none with `unit`: every
// value a measured point, the loops' unit path); from x0 on n values.
SurfaceRow BelowRow(double x0, int n, int gap, bool unit = false) {
  SurfaceRow row;
  row.x0_mm = x0, row.dx_mm = kGridDx, row.at_points = true;
  for (int k = 0; k < n; ++k) {
    const double x = row.x0_mm + k * kGridDx;
    row.z_mm.push_back(k >= gap && k < gap + 6 ? NAN : static_cast<float>(LowerBead(x)));
    row.variance.push_back(!unit && k >= 200 && k < 204 ? 0.5f : 1.0f);
  }
  return row;
}

// One row; and two, the second 0.37 of a spacing off the first's grid (a
// profiler frame moved sideways between them), shorter, its gap elsewhere,
// weighed 0.3: where one is not known the other stands for both.
std::vector<SurfaceGrid> Surfaces(bool unit = false) {
  auto first = std::make_shared<const SurfaceRow>(BelowRow(-12.0, 481, 100, unit));
  auto second = std::make_shared<const SurfaceRow>(BelowRow(-11.5 + 0.37 * kGridDx, 450, 150, unit));
  return {SurfaceGrid(first, nullptr, 0.0), SurfaceGrid(first, second, 0.3)};
}
SurfaceGrid Below() { return Surfaces()[0]; }

// A new bead over it, its points a third of a spacing off the grid's
// phase, every 37th missing.
struct Points {
  std::vector<float> x, z;
  std::vector<double> exact;  // the x each float x stands for
};
Points NewPoints(double shift, bool dropouts = true) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kNoise);
  Points p;
  for (int j = 0; j < 401; ++j) {
    if (dropouts && j % 37 == 5) continue;
    const double x = -10.0 + kGridDx / 3.0 + j * kGridDx, u = (x - shift - 0.3) / 3.0;
    const double top = std::abs(u) < 1.0 ? 1.2 + 1.5 * std::sqrt(1.0 - u * u) : 0.0;
    p.x.push_back(static_cast<float>(x));
    p.exact.push_back(x);
    p.z.push_back(static_cast<float>(std::max(LowerBead(x - shift), top) + noise(rng)));
  }
  return p;
}

// The definitions, point by point (registration.cc's loops).
double Truncated(const Points& p, const SurfaceGrid& below, double s, double lo, double hi) {
  const double noise2 = kNoise * kNoise, cap = kTau * kTau / noise2;
  double sum = 0.0;
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    if (p.x[i] < lo || p.x[i] > hi) continue;
    const SurfaceGrid::Sample b = below.SampleAt(p.x[i] - s);
    const double d = p.z[i] - b.z;
    sum += std::isnan(d) ? cap : std::min(d * d / (noise2 * (1.0 + b.variance)), cap);
  }
  return sum;
}

// How far the float sums may stray from these: the cost's and the
// gradient's rounding of their terms (below), and what the float x of the
// points moves each term by. The grid path puts point i at the first
// point's x plus i spacings; each float x is up to half a float's step
// from there. A term moves by its x-derivative times that: 2 d g / v for
// the cost, 2 g^2 / v for the gradient.
struct Bounds {
  double cost = 0.0, gradient = 0.0, gradient_size = 0.0;
};
PointsOnGrid::Local Local(const Points& p, const SurfaceGrid& below, double s, Bounds& bounds) {
  const double noise2 = kNoise * kNoise, cap = kTau * kTau / noise2;
  PointsOnGrid::Local l;
  bounds = {};
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    const SurfaceGrid::Sample b = below.SampleAt(p.x[i] - s);
    const double d = p.z[i] - b.z, v = noise2 * (1.0 + b.variance), chi2 = d * d / v;
    if (!(chi2 < cap)) {
      l.cost += cap;
      continue;
    }
    l.cost += chi2, l.gradient += 2.0 * d * b.slope / v, l.curvature += 2.0 * b.slope * b.slope / v;
    const double off = std::abs(p.x[i] - (p.x[0] + (p.exact[i] - p.exact[0])));
    bounds.gradient_size += std::abs(2.0 * d * b.slope / v);
    bounds.cost += 2.0 * std::abs(d * b.slope) / v * off;
    bounds.gradient += 2.0 * b.slope * b.slope / v * off;
  }
  return l;
}

// Each term is rounded in floats: z to 2e-7 mm at these heights, so a
// squared gain under the cap moves by at most 2 tau 2e-7 / noise^2
// (2.4e-4) and a sum of 400 terms by 0.1. Sums of terms of either sign
// (the gradient) or of one (the curvature) add in floats, about 50 to a
// lane, each addition rounding by 6e-8 of the sum so far: 1e-5 of the
// terms' sizes bounds it.
constexpr double kSumRounding = 0.1, kAddedRounding = 1e-5;

// Both builds of the loops (part_kernel.h): the baseline, and the one this
// processor runs (AVX2 where it can).
const std::vector<const PartKernel*> kKernels{&BaselinePartKernel(), &ActivePartKernel()};

TEST(GridCosts, EightAtATimeTheyAreTheDefinitionsToAFloatsRounding) {
  std::vector<SurfaceGrid> surfaces = Surfaces(), unit = Surfaces(true);
  surfaces.insert(surfaces.end(), unit.begin(), unit.end());
  for (const SurfaceGrid& below : surfaces) {
    SCOPED_TRACE(below.row(1) ? "two rows" : "one row");
    SCOPED_TRACE(below.row(0)->variance[200] == 1.0f ? "unit variance" : "a stretch bridged");
    const double truth = 0.137;
    const Points p = NewPoints(truth);
    for (const PartKernel* kernel : kKernels) {
      SCOPED_TRACE(kernel->name);
      PointsOnGrid grid;
      grid.UseKernel(*kernel);
      ASSERT_TRUE(grid.Make(p.x, p.z, below));
      const double noise2 = kNoise * kNoise, cap = kTau * kTau / noise2;
      for (double s : {-2.9, -0.31, 0.0, 0.0123, truth, 0.25, 1.77}) {
        for (double margin : {0.0, 3.0}) {
          const double lo = -12.0 + margin, hi = 12.0 - margin;
          EXPECT_NEAR(grid.TruncatedCost(s, noise2, cap, lo, hi), Truncated(p, below, s, lo, hi), kSumRounding) << s;
        }
        Bounds b;
        const PointsOnGrid::Local want = Local(p, below, s, b), got = grid.LocalCost(s, noise2, cap);
        EXPECT_NEAR(got.cost, want.cost, kSumRounding + b.cost) << s;
        EXPECT_NEAR(got.gradient, want.gradient, kAddedRounding * b.gradient_size + b.gradient) << s;
        EXPECT_NEAR(got.curvature, want.curvature, kAddedRounding * want.curvature) << s;
      }
    }
  }
}

TEST(GridCosts, WhereTheSurfacesAgreeIsCountedAsPointByPoint) {
  for (const SurfaceGrid& below : Surfaces()) {
    SCOPED_TRACE(below.row(1) ? "two rows" : "one row");
    const Points p = NewPoints(0.137);
    for (const PartKernel* kernel : kKernels) {
      SCOPED_TRACE(kernel->name);
      PointsOnGrid grid;
      grid.UseKernel(*kernel);
      ASSERT_TRUE(grid.Make(p.x, p.z, below));
      const double feature_slope = 3.0 * kNoise / kGridDx;
      for (double s : {-0.31, 0.0, 0.137, 0.25}) {
        double sum = 0.0;
        int points = 0, features = 0;
        for (std::size_t i = 0; i < p.x.size(); ++i) {
          const SurfaceGrid::Sample b = below.SampleAt(p.x[i] - s);
          const double d = p.z[i] - b.z;
          if (!(std::abs(d) <= kTau)) continue;
          sum += d * d, ++points, features += std::abs(b.slope) > feature_slope;
        }
        const PointsOnGrid::Agreement a = grid.Agree(s, kTau, feature_slope);
        // A point within a float's rounding of tau or of the feature slope
        // may count on one side or the other: none here is.
        EXPECT_EQ(a.points, points) << s;
        EXPECT_EQ(a.features, features) << s;
        EXPECT_NEAR(a.sum_d2, sum, 1e-5 * sum) << s;
      }
    }
  }
}

TEST(GridCosts, TheSurfaceBelowAtEachPointIsItsSample) {
  // With points missing, and with every grid point measured (the points
  // taken as they are).
  for (bool dropouts : {true, false})
    for (const SurfaceGrid& below : Surfaces()) {
      SCOPED_TRACE(below.row(1) ? "two rows" : "one row");
      SCOPED_TRACE(dropouts ? "points missing" : "every point");
      const Points p = NewPoints(0.137, dropouts);
      PointsOnGrid grid;
      ASSERT_TRUE(grid.Make(p.x, p.z, below));
      std::vector<float> under;
      for (double s : {-2.9, 0.0, 0.137}) {
        grid.BelowAt(s, under);
        ASSERT_EQ(under.size(), p.x.size());
        for (std::size_t i = 0; i < p.x.size(); ++i) {
          const SurfaceGrid::Sample b = below.SampleAt(p.x[i] - s);
          EXPECT_EQ(std::isnan(under[i]), std::isnan(b.z)) << s << " " << i;
          if (std::isnan(b.z)) continue;
          // A float's rounding of z, and of x moved along the slope (as above).
          const double off = std::abs(p.x[i] - (p.x[0] + (p.exact[i] - p.exact[0])));
          EXPECT_NEAR(under[i], b.z, 1e-6 + std::abs(b.slope) * off) << s << " " << i;
        }
      }
    }
}

TEST(GridCosts, PointsOffTheGridOrRowsOfOtherSpacingsAreLeftToThePointByPointPath) {
  const SurfaceGrid below = Below();
  Points p = NewPoints(0.0);
  PointsOnGrid grid;
  EXPECT_TRUE(grid.Make(p.x, p.z, below));
  p.x[17] += static_cast<float>(0.2 * kGridDx);  // one point off the spacing's grid
  EXPECT_FALSE(grid.Make(p.x, p.z, below));
  const Points q = NewPoints(0.0);
  SurfaceRow row = *below.single_row(), coarser = row;
  coarser.dx_mm *= 1.5;  // a layer below scanned at another spacing
  const SurfaceGrid two(std::make_shared<const SurfaceRow>(row), std::make_shared<const SurfaceRow>(coarser), 0.5);
  EXPECT_FALSE(grid.Make(q.x, q.z, two));
  row.at_points = false;  // a fine resampling of points, not the points
  EXPECT_FALSE(grid.Make(q.x, q.z, SurfaceGrid(row)));
}

}  // namespace
}  // namespace bead::part
