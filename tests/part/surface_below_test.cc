// The layer below as a surface (part/surface_below.h): a stored profile's
// own points kept as its grid where they lie on one, blended between two
// profiles along the path, and the same surface where they do not.
#include "libbead/part/surface_below.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace bead::part {
namespace {

constexpr double kDx = 0.05;

// A profile at `path` of the surface z = f(x) on points x0 + j dx, j < n,
// those in `missing` left out.
template <class F>
StoredProfile Profile(double path, double x0, int n, F f, std::initializer_list<int> missing = {}) {
  StoredProfile p;
  p.path_mm = path, p.spacing_mm = kDx;
  for (int j = 0; j < n; ++j) {
    if (std::find(missing.begin(), missing.end(), j) != missing.end()) continue;
    const double x = x0 + j * kDx;
    p.x_mm.push_back(static_cast<float>(x));
    p.z_mm.push_back(static_cast<float>(f(x)));
  }
  return p;
}

double Wave(double x) { return 0.3 * std::sin(2.0 * x) + 0.05 * x; }

// The points' own linear interpolation at x, with its variance over one
// point's, (1 - t)^2 + t^2 (NaN where unknown).
SurfaceRow::Sample Between(const StoredProfile& p, double x) {
  for (std::size_t j = 0; j + 1 < p.x_mm.size(); ++j)
    if (p.x_mm[j] <= x && x <= p.x_mm[j + 1]) {
      const double t = (x - p.x_mm[j]) / (p.x_mm[j + 1] - p.x_mm[j]);
      return {(1 - t) * p.z_mm[j] + t * p.z_mm[j + 1], (1 - t) * (1 - t) + t * t, NAN};
    }
  return {NAN, 0.0, NAN};
}

TEST(SurfaceBelow, UniformPointsAreTheirOwnGridAndShortDropoutsAreBridged) {
  // Two points missing (a 0.15 mm gap, bridged) and 30 (1.55 mm: not).
  std::initializer_list<int> missing = {40, 41};
  StoredProfile p = Profile(0.0, -10.0, 401, Wave, missing);
  for (int j = 0; j < 30; ++j) {
    const auto at =
        std::find_if(p.x_mm.begin(), p.x_mm.end(), [&](float x) { return x > -10.0 + (200 + j) * kDx - 1e-4; });
    const auto k = at - p.x_mm.begin();
    p.x_mm.erase(at), p.z_mm.erase(p.z_mm.begin() + k);
  }
  const SurfaceRow row = RowOf(p, 1.0);
  ASSERT_TRUE(row.at_points);
  EXPECT_NEAR(row.dx_mm, kDx, 1e-6);
  for (double x = -9.99; x < 9.99; x += 0.0137) {
    const SurfaceRow::Sample want = Between(p, x), got = row.SampleAt(x);
    if (std::isnan(want.z) || (x > -10.0 + 199 * kDx && x < -10.0 + 230 * kDx)) {
      EXPECT_TRUE(std::isnan(got.z)) << x;  // the long gap: unknown
      continue;
    }
    // Linear between the points, to a float's rounding of z.
    EXPECT_NEAR(got.z, want.z, 1e-6) << x;
    if (x > -10.0 + 39 * kDx && x < -10.0 + 42 * kDx) continue;  // the bridge's own variance
    // The fraction t between two points: the grid's against the float
    // points' own, up to half a float's step at 10 mm over a spacing
    // (1e-5) apart; the variance's slope in t is at most 2.
    EXPECT_NEAR(got.variance, want.variance, 4e-5) << x;
  }
}

// Points lost beside a bead's wall (a triangulation shadow: the surface
// drops by more than the gap is long) are no ramp: each side's height is
// held to the gap's middle, where the wall is put. (Bridged as a ramp, the
// next layer's bead over it was measured +9 % on an independent wall: the
// ramp under the old bead's top made its top a gain.) A gentle gap is
// still bridged linearly.
TEST(SurfaceBelow, PointsLostAtAWallAreAStepNotARamp) {
  const auto wall = [](double x) { return x < 0.02 ? 3.0 : 0.0; };     // a 3 mm wall between x = 0 and 0.05
  const StoredProfile p = Profile(0.0, -2.0, 81, wall, {40, 41, 42});  // x = 0, 0.05, 0.1 lost
  const SurfaceRow row = RowOf(p, 1.0);
  ASSERT_TRUE(row.at_points);
  // The gap from x = -0.05 (3 mm) to 0.15 (0 mm): 3 mm up to its middle, 0 beyond.
  EXPECT_NEAR(row.At(-0.05), 3.0, 1e-6);
  EXPECT_NEAR(row.At(0.0), 3.0, 1e-6);
  EXPECT_NEAR(row.At(0.1), 0.0, 1e-6);
  EXPECT_NEAR(row.At(0.15), 0.0, 1e-6);
  // A slope of 0.5 across the same gap: linear.
  const StoredProfile gentle = Profile(0.0, -2.0, 81, [](double x) { return 0.5 * x; }, {40, 41, 42});
  const SurfaceRow bridged = RowOf(gentle, 1.0);
  EXPECT_NEAR(bridged.At(0.05), 0.025, 1e-6);
}

TEST(SurfaceBelow, EveryGridPointMeasuredIsTheRowAsItIs) {
  const StoredProfile p = Profile(0.0, -10.0, 401, Wave);
  const SurfaceRow row = RowOf(p, 1.0);
  ASSERT_TRUE(row.at_points);
  ASSERT_EQ(row.z_mm.size(), p.z_mm.size());
  EXPECT_TRUE(std::equal(row.z_mm.begin(), row.z_mm.end(), p.z_mm.begin()));
  EXPECT_NEAR(row.x0_mm, -10.0, 1e-6);
  EXPECT_NEAR(row.dx_mm, kDx, 1e-6);
  EXPECT_TRUE(std::all_of(row.variance.begin(), row.variance.end(), [](float v) { return v == 1.0f; }));
}

TEST(SurfaceBelow, PointsOffAGridAreResampledFinelyAndKeepTheirInterpolation) {
  StoredProfile p = Profile(0.0, -10.0, 401, Wave);
  for (std::size_t j = 0; j < p.x_mm.size(); j += 3) p.x_mm[j] += static_cast<float>(0.2 * kDx);
  for (std::size_t j = 0; j < p.x_mm.size(); ++j) p.z_mm[j] = static_cast<float>(Wave(p.x_mm[j]));
  const SurfaceRow row = RowOf(p, 1.0);
  EXPECT_FALSE(row.at_points);
  EXPECT_NEAR(row.dx_mm, kDx / 8, 1e-9);
  // On an eighth of a spacing, the grid's interpolation of the points'
  // interpolation is off only in a grid step holding a point (a kink), by
  // at most the slope change there over 4 times the step: |z''| <= 1.2
  // over two segments of at most 1.2 spacings, 0.072, so 1.1e-4 mm.
  for (double x = -9.9; x < 9.9; x += 0.0137) EXPECT_NEAR(row.SampleAt(x).z, Between(p, x).z, 1.2e-4) << x;
}

TEST(SurfaceBelow, TwoProfilesAreBlendedAlongThePathOnOneGridOrTwo) {
  auto flat = [](double z) { return [z](double) { return z; }; };
  for (double second_x0 : {-9.9, -9.9 + 0.5 * kDx}) {  // the same grid, then half a spacing off it
    SurfaceBelow below;
    below.BeginLayer(0);
    below.Keep(Profile(10.0, -10.0, 401, flat(1.0)));
    below.Keep(Profile(12.0, second_x0, 401, flat(2.0)));
    below.BeginLayer(1);
    const std::optional<SurfaceGrid> g = below.At(10.5, nullptr);
    ASSERT_TRUE(g);
    EXPECT_EQ(g->single_row() != nullptr, second_x0 == -9.9) << second_x0;
    // A quarter of the way: 1.25, its variance (3/4)^2 + (1/4)^2 on points.
    const SurfaceGrid::Sample mid = g->SampleAt(0.0 + 0.0 * kDx);
    EXPECT_NEAR(mid.z, 1.25, 1e-6);
    if (second_x0 == -9.9) {
      EXPECT_NEAR(mid.variance, 0.625, 1e-6);
    }
    // Where only the first was scanned (left of the second's start), it
    // stands for both.
    EXPECT_NEAR(g->At(-9.95), 1.0, 1e-6);
    EXPECT_NEAR(g->At(10.05), 2.0, 1e-6);  // and only the second
  }
}

TEST(SurfaceBelow, ASurfaceHandedOutOutlivesTheLayersThatReuseTheirMemory) {
  // Layers 0, 1 and 2 flat at heights 1, 2, 3; each layer's rows and
  // buffers reuse those of the one before (SurfaceBelow::Spare), but not a
  // surface a caller still holds (a row waiting for its layer's groove).
  auto flat = [](double z) { return [z](double) { return z; }; };
  SurfaceBelow below;
  std::optional<SurfaceGrid> held_single, held_blend;
  for (int layer = 0; layer < 4; ++layer) {
    below.BeginLayer(layer);
    if (layer == 1) held_single = below.At(10.0, nullptr), held_blend = below.At(11.0, nullptr);
    if (layer >= 1) {
      const std::optional<SurfaceGrid> g = below.At(11.0, nullptr);
      ASSERT_TRUE(g) << layer;
      EXPECT_NEAR(g->At(0.0), layer, 1e-6) << layer;  // the layer below's height
    }
    for (double path : {10.0, 12.0}) {
      StoredProfile p = Profile(path, -10.0, 401, flat(layer + 1.0));
      // Its buffers from the layer before's profiles where there are any.
      std::vector<float> x = below.Spare(), z = below.Spare();
      EXPECT_EQ(x.empty(), layer == 0) << layer;  // from layer 1 on, the layer before let go
      x.assign(p.x_mm.begin(), p.x_mm.end()), z.assign(p.z_mm.begin(), p.z_mm.end());
      p.x_mm = std::move(x), p.z_mm = std::move(z);
      below.Keep(std::move(p));
    }
  }
  ASSERT_TRUE(held_single && held_blend);
  EXPECT_NEAR(held_single->At(0.0), 1.0, 1e-6);
  EXPECT_NEAR(held_blend->At(0.0), 1.0, 1e-6);
}

// A layer whose beads' areas follow a trend along the path (a ramp, with a
// profile's noise on it) and step once, between profiles 19 and 20 (a
// corner's bulge beginning). The blend between two profiles follows a
// trend; where the step lies between them it cannot see: a place a share w
// of the way from the first to the second has the second's surface with
// chance w, the first's with 1 - w, and the blend is off by w (1 - w) D^2
// in variance. Nothing at a profile's own place, and nothing between two
// that only follow the trend away from the step: the noise alone makes
// none.
TEST(SurfaceBelow, AStepInTheLayerBelowBetweenItsProfilesIsAVarianceWhereItsTrendIsNone) {
  const auto flat = [](double z) { return [z](double) { return z; }; };
  const auto area = [](int k, double step) {
    return 10.0 + 0.02 * k + 0.01 * std::sin(2.3 * k) + (k >= 20 ? step : 0.0);
  };
  for (const double step : {0.0, 2.0}) {
    SurfaceBelow below;
    below.BeginLayer(0);
    for (int k = 0; k < 40; ++k) {
      StoredProfile p = Profile(0.5 * k, -10.0, 41, flat(1.0));
      p.area_mm2 = area(k, step);
      below.Keep(std::move(p));
    }
    below.BeginLayer(1);
    const BelowChange across = below.ChangeAt(0.5 * 19 + 0.3 * 0.5);
    EXPECT_NEAR(across.w, 0.3, 1e-9);
    EXPECT_NEAR(across.change_mm2, area(20, step) - area(19, step), 1e-12);
    const double d = area(20, step) - area(19, step);
    EXPECT_NEAR(across.Variance(), step > 0.0 ? 0.3 * 0.7 * d * d : 0.0, 1e-12) << step;
    EXPECT_EQ(below.ChangeAt(0.5 * 10).Variance(), 0.0) << "at a profile's own place";
    // Away from the step, none; beside it, what the pair's own change (the
    // trend's, 0.02 mm^2 a profile) leaves: under a thousandth of the step's.
    for (int k = 0; k + 1 < 40; ++k) {
      const double v = below.ChangeAt(0.5 * k + 0.25).Variance();
      if (step == 0.0 || k < 17 || k > 21) {
        EXPECT_EQ(v, 0.0) << step << " " << k;
      } else if (k != 19) {
        EXPECT_LT(v, 1e-3 * 0.25 * d * d) << k;
      }
    }
  }
}

// A layer whose beads' areas curve along the path (a quadratic, its
// profiles 4 mm apart: a slow profiler's): the blend between two profiles
// is straight, and misses the curve by w (1 - w) / 2 times its second
// difference over the pair. The bend's variance is that miss squared at
// every place between profiles; nothing where the areas follow a line.
// (Profiles 3-4 mm apart along the twin's contour, whose beads follow a
// 40 mm wave: with no such term 14 % of the rows lay beyond three sigmas;
// with it, 3-4 %.)
TEST(SurfaceBelow, ALayerCurvingAlongThePathBetweenItsProfilesIsTheBlendsVariance) {
  const auto flat = [](double z) { return [z](double) { return z; }; };
  for (const double curve : {0.0, 0.05}) {
    const auto area = [curve](double path) { return 12.0 + 0.1 * path + curve * path * path; };
    SurfaceBelow below;
    below.BeginLayer(0);
    for (int k = 0; k < 10; ++k) {
      StoredProfile p = Profile(4.0 * k, -10.0, 41, flat(1.0));
      p.area_mm2 = area(4.0 * k);
      below.Keep(std::move(p));
    }
    below.BeginLayer(1);
    // (Between the layer's third profile and its third last: a pair at an
    // end has its trend from one side, which a curve leaves by its second
    // difference, and is taken for a step, its variance the step's.)
    for (double path = 8.3; path < 28.0; path += 1.3) {
      const BelowChange c = below.ChangeAt(path);
      const double blend = (1.0 - c.w) * area(4.0 * std::floor(path / 4.0)) + c.w * area(4.0 * std::ceil(path / 4.0));
      EXPECT_NEAR(std::sqrt(c.BendVariance()), std::abs(blend - area(path)), 1e-9) << curve << " " << path;
    }
  }
}

// A layer below scanned every 6 mm of path (a slow profiler): no place
// between two of its profiles is known, wherever it lies between them (the
// farther neighbour's distance decided it, so a layer whose places fell
// just before the layer below's was refused and one whose fell after them
// was measured, its intervals covering two rows in three); every 4 mm,
// every place is, and past the layer's ends within 5 mm of its last.
TEST(SurfaceBelow, ProfilesFartherApartThanTheGapLeaveNoPlaceBetweenThemKnown) {
  const auto flat = [](double z) { return [z](double) { return z; }; };
  for (const double apart : {4.0, 6.0}) {
    SurfaceBelow below;
    below.BeginLayer(0);
    for (int k = 0; k < 8; ++k) below.Keep(Profile(apart * k + 1.0, -10.0, 41, flat(1.0)));
    below.BeginLayer(1);
    for (double phase : {0.1, 0.5, 1.8, 3.0}) {
      std::string why;
      const bool known = below.At(apart * 3 + 1.0 + phase, &why).has_value();
      EXPECT_EQ(known, apart < 5.0) << apart << " " << phase;
      if (!known) {
        EXPECT_NE(why.find("apart"), std::string::npos) << why;
      }
    }
    EXPECT_TRUE(below.At(apart * 7 + 1.0 + 4.9, nullptr).has_value()) << apart << ": 4.9 mm past the last";
    EXPECT_FALSE(below.At(apart * 7 + 1.0 + 5.1, nullptr).has_value()) << apart << ": 5.1 mm past the last";
  }
}

}  // namespace
}  // namespace bead::part
