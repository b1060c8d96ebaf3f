// What the sensor can see of an outline: exact areas checked against
// closed forms and against dense ray casting.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "libbead/sim/bead_shapes.h"
#include "libbead/sim/sensor_model.h"

namespace bead::sim {
namespace {

// Chord polygon of a quarter arc of radius r in m steps misses m segments
// of (r^2 / 2) (d - sin d), d = (pi / 2) / m.
double MissingSegments(double r, int m) {
  const double d = std::numbers::pi / 2 / m;
  return m * r * r / 2 * (d - std::sin(d));
}

TEST(BeadShapes, RoundedRectangleAreaIsTheClosedFormLessChordSegments) {
  BeadConfig c;
  c.aspect = 1.6;
  c.bottom_radius_frac = 0.25;
  c.top_radius_frac = 0.35;
  c.outline_vertices = 96;
  const Outline o = UnitBeadOutline(c);
  const int m = (96 - 4) / 4;
  const double closed = 1.6 - (1 - std::numbers::pi / 4) * (2 * 0.25 * 0.25 + 2 * 0.35 * 0.35);
  EXPECT_NEAR(OutlineArea(o), closed - 2 * MissingSegments(0.25, m) - 2 * MissingSegments(0.35, m), 1e-12);
  const BeadDims d = OutlineDims(o);
  EXPECT_NEAR(d.max_width_mm, 1.6, 1e-12);
  EXPECT_NEAR(d.contact_width_mm, 1.6 - 2 * 0.25, 1e-12);
  EXPECT_NEAR(d.height_mm, 1.0, 1e-12);
}

// Straight above, a bead without undercut hides nothing.
TEST(VisibleArea, NoUndercutFromStraightAboveIsTheTrueArea) {
  for (const Outline& o : {ParabolaOutline(6.0, 2.0, 0.4, 301), TrapezoidOutline(6.0, 3.0, 2.0, -1.0)})
    EXPECT_NEAR(VisibleArea(o, {}, std::nullopt), OutlineArea(o), 1e-9);
}

// A rectangle with two bottom quarter-circle corners of radius r seen from
// straight above hides (1 - pi/4) r^2 per corner (issue 5's analytic check).
TEST(VisibleArea, BottomCornersHideOneMinusQuarterPiRSquaredEach) {
  BeadConfig c;
  c.aspect = 2.0;
  c.bottom_radius_frac = 0.3;
  c.top_radius_frac = 0.0;
  c.outline_vertices = 4004;  // 1000 chords per arc
  const Outline o = UnitBeadOutline(c);
  const double hidden = VisibleArea(o, {}, std::nullopt) - OutlineArea(o);
  const int m = 1000;
  const double d = std::numbers::pi / 2 / m;
  // Exactly, for the chord polygon: the r x r square less the polygonal quarter sector.
  EXPECT_NEAR(hidden, 2 * (0.09 - m * 0.09 / 2 * std::sin(d)), 1e-12);
  // And the closed form, to the chord error.
  EXPECT_NEAR(hidden, 2 * (1 - std::numbers::pi / 4) * 0.09, 2 * MissingSegments(0.3, m) + 1e-12);
}

// The exact visible area equals the integral of a dense fan rendering,
// within the rendering's sampling bound (height x ray spacing).
TEST(VisibleArea, MatchesDenseFanRendering) {
  BeadConfig c;
  const Outline o = ScaledOutline(UnitBeadOutline(c), OutlineArea(UnitBeadOutline(c)), 14.0, 3.0);
  const SensorPose pose{0.01, 0.0, 0.2};
  const Fan fan{-5.0, 95.0};
  const int n = 40001;
  std::vector<float> target(n), x(n), z(n);
  for (int j = 0; j < n; ++j) target[j] = static_cast<float>(-2.0 + 10.0 * j / (n - 1));
  RenderProfileFan(o, pose, fan, target, x, z);
  // Area between the seen points and the surface line, perpendicular to it.
  const double cs = std::cos(pose.roll_rad), sn = std::sin(pose.roll_rad);
  double area = 0.0;
  for (int j = 0; j + 1 < n; ++j) {
    auto s = [&](int k) { return cs * x[k] + sn * (z[k] - pose.z_offset_mm); };
    auto h = [&](int k) { return -sn * x[k] + cs * (z[k] - pose.z_offset_mm); };
    area += 0.5 * (h(j) + h(j + 1)) * (s(j + 1) - s(j));
  }
  const double visible = VisibleArea(o, pose, fan);
  EXPECT_GT(visible, OutlineArea(o));
  EXPECT_NEAR(area, visible, OutlineDims(o).height_mm * 10.0 / (n - 1) + 1e-4);  // + float32 rounding
}

}  // namespace
}  // namespace bead::sim
