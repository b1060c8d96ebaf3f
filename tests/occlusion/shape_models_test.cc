#include "libbead/occlusion/shape_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "libbead/sim/bead_shapes.h"
#include "libbead/sim/sensor_model.h"

namespace bead::occlusion {
namespace {

// A circle (n = 2, a = b = r) standing on its lowest point (c = 0) is a
// half disc; lifted to c = r it is the whole disc minus nothing: pi r^2 / 2
// above the widest point and the rest below.
TEST(CutSuperellipse, AreasOfCircles) {
  const CutSuperellipse half{2.0, 2.0, 0.0, 2.0};
  EXPECT_NEAR(half.TrueArea(), std::numbers::pi * 2.0, 1e-10);
  EXPECT_NEAR(half.VisibleArea(), half.TrueArea(), 1e-12);
  // Lifted by r/2: the cut circle's segment below the widest point is
  // r^2 (asin(1/2) + (1/2) sqrt(3/4)) for r = 2 (the area of a disc between
  // its centre line and a chord r/2 below).
  const CutSuperellipse lifted{2.0, 2.0, 1.0, 2.0};
  const double below = 4.0 * (std::asin(0.5) + 0.5 * std::sqrt(0.75));
  EXPECT_NEAR(lifted.TrueArea(), std::numbers::pi * 2.0 + below, 1e-9);
  // Seen from above, the band below the widest point looks full: 2 a c.
  EXPECT_NEAR(lifted.VisibleArea() - lifted.TrueArea(), 2 * 2.0 * 1.0 - below, 1e-9);
  EXPECT_NEAR(lifted.ContactWidth(), 2 * std::sqrt(3.0), 1e-12);
}

// The twin's polygon of the same shape has the same area, to its chords.
TEST(CutSuperellipse, MatchesTheTwinsPolygon) {
  sim::BeadConfig c;
  c.shape = sim::BeadConfig::Shape::kSuperellipse;
  c.exponent = 2.6;
  c.center_lift_frac = 0.4;
  c.aspect = 1.5;
  c.outline_vertices = 4001;  // chord error about P^3 kappa / (12 V^2) ~ 1e-6
  const double b = 1.0 / 1.4;
  const CutSuperellipse m{0.75, b, 0.4 * b, 2.6};
  EXPECT_NEAR(sim::OutlineArea(sim::UnitBeadOutline(c)), m.TrueArea(), 1e-5);  // 10x the chord error
  EXPECT_NEAR(sim::VisibleArea(sim::UnitBeadOutline(c), {}, std::nullopt), m.VisibleArea(), 1e-5);
  double u = 0.3;
  const double p[4] = {m.a, m.b, m.c, m.n};
  EXPECT_NEAR(CutSuperellipse::Envelope(p, u), m.c + m.b * std::pow(1 - std::pow(u / m.a, m.n), 1 / m.n), 1e-12);
  EXPECT_EQ(CutSuperellipse::Envelope(p, 0.8), 0.0);
}

// Issue 5's analytic check: two bottom quarter-circle corners of radius r
// seen from straight above hide exactly (1 - pi/4) r^2 each.
TEST(RoundedRectangle, BottomCornersHideOneMinusQuarterPiRSquaredEach) {
  const RoundedRectangle m{6.0, 3.0, 0.5, 0.8};
  EXPECT_NEAR(m.VisibleArea() - m.TrueArea(), 2 * (1 - std::numbers::pi / 4) * 0.8 * 0.8, 1e-12);
  const double p[3] = {6.0, 3.0, 0.5};
  EXPECT_DOUBLE_EQ(RoundedRectangle::Envelope(p, 0.0), 3.0);
  EXPECT_NEAR(RoundedRectangle::Envelope(p, 3.0 - 0.5 + 0.3), 3.0 - 0.5 + std::sqrt(0.25 - 0.09), 1e-12);
}

TEST(ParabolicCap, HidesNothing) {
  const ParabolicCap m{6.0, 2.0};
  EXPECT_DOUBLE_EQ(m.TrueArea(), 8.0);
  EXPECT_DOUBLE_EQ(m.VisibleArea(), m.TrueArea());
}

// The fan's shadow beside a bead centred under the fan (both rays outward)
// is two triangles c^2 tan(alpha) / 2, plus the sliver the formula leaves
// out where the ray grazes the shape above its widest point: the twin's
// exact visible area agrees within 0.05 % of the bead's area.
TEST(FanShadow, MatchesTheTwinsExactVisibleArea) {
  sim::BeadConfig c;
  c.shape = sim::BeadConfig::Shape::kSuperellipse;
  c.outline_vertices = 4001;
  const sim::Outline unit = sim::UnitBeadOutline(c);
  const sim::Outline o = sim::ScaledOutline(unit, sim::OutlineArea(unit), 14.0, 0.0);
  const sim::Fan fan{0.0, 95.0};
  const double with = sim::VisibleArea(o, {}, fan), without = sim::VisibleArea(o, {}, std::nullopt);
  const sim::BeadDims d = sim::OutlineDims(o);
  // Widest point: where the outline's x is extreme.
  double c_height = 0, x_max = -1;
  for (const auto& p : o)
    if (p.x() > x_max) x_max = p.x(), c_height = p.y();
  const double triangles = FanShadowArea(c_height, -d.max_width_mm / 2, d.max_width_mm / 2, 0.0, 95.0);
  EXPECT_GT(with - without, triangles);
  EXPECT_NEAR(with - without, triangles, 0.0005 * 14.0);
}

}  // namespace
}  // namespace bead::occlusion
