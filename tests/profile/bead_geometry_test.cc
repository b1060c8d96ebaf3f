// Bead geometry of analytic shapes with exact areas, as the sensor sees
// them. Tolerances come from the point spacing dx and the noise:
//  - area: a wall standing somewhere between the last surface point and
//    the first bead point is taken as the trapezoid between them, so each
//    edge errs by at most h_edge * dx / 2: at most H * dx for the bead
//    (sloped walls do better: bead_edge_test.cc);
//  - width: each edge lies within one spacing of the truth, 2 dx;
//  - height: the robust maximum (median of three) is the apex or a
//    neighbour within 2 dx of it: a drop of curvature * (2 dx)^2 / 2.
#include "libbead/profile/bead_geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "libbead/profile/profile_processor.h"
#include "tests/support/synthetic.h"

namespace bead {
namespace {

using test::kLeft;
using test::kRight;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

BeadGeometry Measure(const test::Synthetic& p) { return MeasureProfile(p.view(), kLeft, kRight); }

// Largest spacing between consecutive measured points: what bounds the edges.
double MaxGap(const test::Synthetic& p) {
  double gap = 0.0, last = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> xs;
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (std::isfinite(p.z[i])) xs.push_back(p.x[i]);
  std::sort(xs.begin(), xs.end());
  for (double x : xs) {
    if (std::isfinite(last)) gap = std::max(gap, x - last);
    last = x;
  }
  return gap;
}

struct Shape {
  const char* name;
  sim::Outline outline;
  double area, width, height;
  double apex_curvature;  // 1/mm at the top (0: flat top)
};

std::vector<Shape> Shapes() {
  return {
      {"rectangle 10 x 2", sim::RectangleOutline(10.0, 2.0, 0.5), 20.0, 10.0, 2.0, 0.0},
      {"semicircle r 4", sim::SemicircleOutline(4.0, -1.0), std::numbers::pi * 8.0, 8.0, 4.0, 1.0 / 4.0},
      {"parabola 12 x 3", sim::ParabolaOutline(12.0, 3.0), 2.0 * 12.0 * 3.0 / 3.0, 12.0, 3.0, 2 * 3.0 * 4 / 144.0},
      {"trapezoid 10/6 x 2", sim::TrapezoidOutline(10.0, 6.0, 2.0, 1.0), (10.0 + 6.0) * 2.0 / 2.0, 10.0, 2.0, 0.0},
  };
}

// Straight above, no noise: every shape's area, width and height within
// what the spacing allows.
TEST(BeadGeometry, AnalyticShapesWithinSamplingBounds) {
  const auto grid = test::UniformGrid(640);
  for (const Shape& shape : Shapes()) {
    const auto p = test::Render(shape.outline, {0.0, 0.0, 50.0}, grid);
    const double dx = p.spacing();
    const BeadGeometry g = Measure(p);
    ASSERT_TRUE(g.valid()) << shape.name << ": " << StatusName(g.status);
    EXPECT_NEAR(g.area_mm2, shape.area, shape.height * dx) << shape.name;
    EXPECT_NEAR(g.width_mm, shape.width, 2 * dx) << shape.name;
    EXPECT_NEAR(g.height_mm, shape.height, shape.apex_curvature * 2 * dx * dx + 1e-4) << shape.name;
    EXPECT_EQ(g.dropped_points, 0);
  }
}

// The area bound is not slack: refining the grid tenfold shrinks the
// rectangle's error below the coarse grid's bound divided by ten.
TEST(BeadGeometry, AreaErrorShrinksWithSpacing) {
  const auto rect = sim::RectangleOutline(10.0, 2.0, 0.37);
  const auto coarse = test::Render(rect, {}, test::UniformGrid(128));
  const auto fine = test::Render(rect, {}, test::UniformGrid(1280));
  const double e_coarse = std::abs(Measure(coarse).area_mm2 - 20.0);
  const double e_fine = std::abs(Measure(fine).area_mm2 - 20.0);
  EXPECT_LE(e_fine, 2.0 * fine.spacing() + 1e-4);
  EXPECT_LE(e_coarse, 2.0 * coarse.spacing());
}

// A rolled sensor sees the rectangle plus the shadow its far wall casts
// along the rays: a triangle H^2 tan(roll) / 2, which also widens the base
// by H tan(roll). Heights are perpendicular to the fitted line, so the roll
// changes nothing else; runout (the wheel surface moving) changes nothing.
TEST(BeadGeometry, RollAndRunoutLeaveTheSeenAreaUnchanged) {
  const auto grid = test::UniformGrid(640);
  for (double roll_deg : {-5.0, -2.0, 0.0, 1.0, 5.0}) {
    for (double runout : {-0.4, 0.0, 0.7}) {
      const double t = std::abs(std::tan(roll_deg * kDeg));
      const auto p = test::Render(sim::RectangleOutline(10.0, 2.0), {roll_deg * kDeg, 0.3, 50.0 + runout}, grid);
      const double dx = p.spacing();
      const BeadGeometry g = Measure(p);
      ASSERT_TRUE(g.valid()) << roll_deg;
      EXPECT_NEAR(g.area_mm2, 20.0 + 2.0 * 2.0 * t / 2.0, 2.0 * dx) << "roll " << roll_deg << " runout " << runout;
      EXPECT_NEAR(g.width_mm, 10.0 + 2.0 * t, 2 * dx) << "roll " << roll_deg;
      EXPECT_NEAR(g.height_mm, 2.0, 1e-3) << "roll " << roll_deg;
      EXPECT_NEAR(g.reference.slope, std::tan(roll_deg * kDeg), 1e-5);
    }
  }
  // Smooth shapes have no shadow at these rolls (their walls are less steep
  // than 90 - 5 degrees except within a sliver at the semicircle's base).
  for (const Shape& shape : Shapes()) {
    if (shape.apex_curvature == 0.0) continue;
    const auto p = test::Render(shape.outline, {4.0 * kDeg, -0.2, 30.0}, grid);
    const BeadGeometry g = Measure(p);
    ASSERT_TRUE(g.valid());
    EXPECT_NEAR(g.area_mm2, shape.area, shape.height * p.spacing()) << shape.name;
  }
}

// Noise sigma on each height: the area integral sums about n = width / dx
// independent errors of sigma * dx, and the reference line's offset error
// sigma / sqrt(n_ref) spreads over the width. 5-sigma bound on both, plus
// the sampling bound.
TEST(BeadGeometry, NoiseDropoutsAndSpikes) {
  sim::SensorNoise noise;
  noise.z_sigma_mm = 0.01;
  noise.dropout_prob = 0.08;
  noise.spike_prob = 0.02;
  noise.spike_mm = 3.0;
  const auto grid = test::UniformGrid(640);
  for (const Shape& shape : Shapes()) {
    for (unsigned seed = 1; seed <= 10; ++seed) {
      const auto p = test::Render(shape.outline, {1.5 * kDeg, 0.0, 45.0}, grid, noise, seed);
      const BeadGeometry g = Measure(p);
      ASSERT_TRUE(g.valid()) << shape.name << " seed " << seed << ": " << StatusName(g.status);
      const double dx = p.spacing(), gap = MaxGap(p);
      const double n = shape.width / dx, n_ref = g.reference.points_used;
      const double noise_area = 5.0 * noise.z_sigma_mm * (dx * std::sqrt(n) + shape.width / std::sqrt(n_ref));
      const double shadow = shape.apex_curvature == 0.0 ? shape.height * shape.height * std::tan(1.5 * kDeg) / 2 : 0.0;
      EXPECT_NEAR(g.area_mm2, shape.area + shadow, shape.height * gap + noise_area) << shape.name << " seed " << seed;
      EXPECT_NEAR(g.width_mm, shape.width + (shadow > 0 ? shape.height * std::tan(1.5 * kDeg) : 0.0), 2 * gap)
          << shape.name << " seed " << seed;
      EXPECT_NEAR(g.height_mm, shape.height, shape.apex_curvature * 2 * gap * gap + 5 * noise.z_sigma_mm)
          << shape.name << " seed " << seed;
    }
  }
}

// Point order and spacing are the sensor's business, not the geometry's.
TEST(BeadGeometry, NonUniformReversedAndUnsortedX) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> step(0.03, 0.13);
  std::vector<float> grid;
  for (double x = -25.0; x <= 25.0; x += step(rng)) grid.push_back(static_cast<float>(x));
  for (const Shape& shape : Shapes()) {
    auto p = test::Render(shape.outline, {0.0, 0.0, 10.0}, grid);
    const BeadGeometry forward = Measure(p);
    ASSERT_TRUE(forward.valid());
    EXPECT_NEAR(forward.area_mm2, shape.area, shape.height * MaxGap(p)) << shape.name;

    std::reverse(p.x.begin(), p.x.end());
    std::reverse(p.z.begin(), p.z.end());
    const BeadGeometry reversed = Measure(p);
    EXPECT_DOUBLE_EQ(reversed.area_mm2, forward.area_mm2);
    EXPECT_DOUBLE_EQ(reversed.width_mm, forward.width_mm);

    std::vector<std::size_t> idx(p.x.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::shuffle(idx.begin(), idx.end(), rng);
    test::Synthetic shuffled;
    for (std::size_t i : idx) {
      shuffled.x.push_back(p.x[i]);
      shuffled.z.push_back(p.z[i]);
    }
    const BeadGeometry unsorted = Measure(shuffled);
    EXPECT_DOUBLE_EQ(unsorted.area_mm2, forward.area_mm2);
    EXPECT_DOUBLE_EQ(unsorted.height_mm, forward.height_mm);
  }
}

// A sensor that marks a dropout by NaN z keeps its x in order, and the
// points are used where they lie; one that reports x reversed gets a sorted
// copy with its dropouts kept in place. Both see the same points: the
// geometry agrees to float rounding (the sums meet the points in a
// different grouping: 1e-5 relative), the counts exactly.
// A sensor that marks a dropout by NaN x leaves the point out altogether,
// so the robust start samples other points (it takes every stride-th point
// the sensor reported); the least-squares refits then agree but for points
// at the edge of the inlier band. A point traded for another there (each
// with a residual <= band = 3.5 rms) moves the line by at most
// 2 band / points_used; allowing two trades gives the tolerances below
// (area: times the width; height: the shift itself; each edge, and the
// centre with them: the shift over the parabola's edge slope 4H/W).
TEST(BeadGeometry, DropoutsInPlaceOrCopiedAgree) {
  sim::SensorNoise noise;
  noise.z_sigma_mm = 0.01;
  noise.dropout_prob = 0.05;
  noise.spike_prob = 0.01;
  noise.spike_mm = 2.0;
  const double width = 9.0, height = 3.0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const auto in_place =
        test::Render(sim::ParabolaOutline(width, height), {0.02, 0.0, 40.0}, test::UniformGrid(640), noise, seed);
    const BeadGeometry a = Measure(in_place);
    ASSERT_TRUE(a.valid()) << "seed " << seed;

    auto reversed = in_place;
    std::reverse(reversed.x.begin(), reversed.x.end());
    std::reverse(reversed.z.begin(), reversed.z.end());
    const BeadGeometry b = Measure(reversed);
    ASSERT_TRUE(b.valid()) << "seed " << seed;
    EXPECT_NEAR(a.area_mm2, b.area_mm2, 1e-5 * a.area_mm2) << "seed " << seed;
    EXPECT_NEAR(a.width_mm, b.width_mm, 1e-5 * a.width_mm) << "seed " << seed;
    EXPECT_NEAR(a.height_mm, b.height_mm, 1e-5 * a.height_mm) << "seed " << seed;
    EXPECT_NEAR(a.center_x_mm, b.center_x_mm, 1e-5) << "seed " << seed;
    EXPECT_EQ(a.bead_points, b.bead_points) << "seed " << seed;
    EXPECT_EQ(a.dropped_points, b.dropped_points) << "seed " << seed;
    EXPECT_EQ(a.reference.points_used, b.reference.points_used) << "seed " << seed;
    EXPECT_EQ(a.reference.points_available, b.reference.points_available) << "seed " << seed;

    auto missing = in_place;
    int dropouts = 0;
    for (std::size_t i = 0; i < missing.x.size(); ++i)
      if (std::isnan(missing.z[i])) missing.x[i] = kNaN, ++dropouts;
    ASSERT_GT(dropouts, 10);
    const BeadGeometry c = Measure(missing);
    ASSERT_TRUE(c.valid()) << "seed " << seed;
    const double shift = 2.0 * 3.5 * a.reference.residual_rms_mm / a.reference.points_used * 2.0;
    EXPECT_NEAR(a.area_mm2, c.area_mm2, shift * width) << "seed " << seed;
    EXPECT_NEAR(a.height_mm, c.height_mm, shift) << "seed " << seed;
    EXPECT_NEAR(a.width_mm, c.width_mm, 2.0 * shift / (4.0 * height / width)) << "seed " << seed;
    EXPECT_NEAR(a.center_x_mm, c.center_x_mm, shift / (4.0 * height / width)) << "seed " << seed;
    EXPECT_EQ(a.dropped_points, c.dropped_points) << "seed " << seed;
    EXPECT_EQ(a.reference.points_available, c.reference.points_available) << "seed " << seed;
  }
}

TEST(BeadGeometry, CentreIsTheAreaCentroid) {
  const auto p = test::Render(sim::TrapezoidOutline(10.0, 10.0, 2.0, 3.25), {}, test::UniformGrid(640));
  EXPECT_NEAR(Measure(p).center_x_mm, 3.25, 0.5 * p.spacing());
  // A right-angled profile: centroid of a triangle is a third from its wall.
  const sim::Outline triangle = {{-3.0, 0.0}, {-3.0, 3.0}, {3.0, 0.0}};
  const auto q = test::Render(triangle, {}, test::UniformGrid(640));
  EXPECT_NEAR(Measure(q).center_x_mm, -3.0 + 6.0 / 3.0, q.spacing());
}

TEST(BeadGeometry, InvalidProfilesSayWhy) {
  const auto grid = test::UniformGrid(640);
  // No bead: the bare surface.
  EXPECT_EQ(Measure(test::Render({}, {}, grid)).status, ProfileStatus::kNoBead);
  // A bead beyond the right reference area (running off the profile's
  // end): not between the areas, so not looked at.
  EXPECT_EQ(Measure(test::Render(sim::RectangleOutline(6.0, 2.0, 27.0), {}, grid)).status, ProfileStatus::kNoBead);
  // A bead reaching into the right reference area.
  EXPECT_EQ(Measure(test::Render(sim::RectangleOutline(6.0, 2.0, 11.0), {}, grid)).status,
            ProfileStatus::kBeadInReferenceArea);
  // A bead whose edge falls in a long dropout.
  auto gap = test::Render(sim::RectangleOutline(6.0, 2.0), {}, grid);
  for (std::size_t i = 0; i < gap.x.size(); ++i)
    if (gap.x[i] > -4.5 && gap.x[i] < -2.0) gap.z[i] = kNaN;
  EXPECT_EQ(Measure(gap).status, ProfileStatus::kBeadEdgeNotSeen);
  // No reference: the left area is dark.
  auto dark = test::Render(sim::RectangleOutline(6.0, 2.0), {}, grid);
  for (std::size_t i = 0; i < dark.x.size(); ++i)
    if (kLeft.Contains(dark.x[i])) dark.z[i] = kNaN;
  const BeadGeometry no_ref = Measure(dark);
  EXPECT_EQ(no_ref.status, ProfileStatus::kNoReference);
  EXPECT_TRUE(std::isnan(no_ref.area_mm2));
  // Too few points: all but eight are missing.
  auto sparse = test::Render(sim::RectangleOutline(6.0, 2.0), {}, grid);
  for (std::size_t i = 8; i < sparse.z.size(); ++i) sparse.z[i] = kNaN;
  EXPECT_EQ(Measure(sparse).status, ProfileStatus::kTooFewPoints);
}

// The bead is looked for between the reference areas, up to 16 points
// into each (bead_geometry.cc, kAreaMargin): a taller block beyond an area
// (the wheel's rim, a clamp) does not take the bead's place, and a film
// below the threshold spreading from the bead's foot is a foot while it
// stays within those 16 points, an edge not seen beyond them.
TEST(BeadGeometry, TheBeadIsLookedForBetweenTheAreas) {
  const auto grid = test::UniformGrid(640);  // 0.078 mm spacing
  const double dx = 50.0 / 639.0;
  // Bead 6 x 2 (12 mm^2); block 20 mm tall from x = 24.3 to the profile's
  // end (0.7 x 20 = 14 mm^2 seen): the larger run, were it looked at.
  const sim::Outline with_block = {{-3.0, 0.0}, {-3.0, 2.0},  {3.0, 2.0},  {3.0, 0.0},
                                   {24.3, 0.0}, {24.3, 20.0}, {26.0, 20.0}};
  const BeadGeometry g = Measure(test::Render(with_block, {}, grid));
  ASSERT_TRUE(g.valid()) << StatusName(g.status);
  EXPECT_NEAR(g.area_mm2, 12.0, 2.0 * dx);  // each edge errs by at most H dx / 2
  EXPECT_NEAR(g.width_mm, 6.0, 2.0 * dx);
  // A 20 um film (above the 1 um noise floor, below the 50 um threshold of
  // a noise-free profile) from the bead's left side to x_end, entering the
  // left area (x < -12) by 1 mm (13 points) or 2.5 mm (32 points).
  auto with_film = [](double x_end) {
    return sim::Outline{{x_end, 0.0}, {x_end, 0.02}, {-3.0, 0.02}, {-3.0, 2.0}, {3.0, 2.0}, {3.0, 0.0}};
  };
  const BeadGeometry near = Measure(test::Render(with_film(-13.0), {}, grid));
  ASSERT_TRUE(near.valid()) << StatusName(near.status);
  EXPECT_NEAR(near.left_edge_x_mm, -13.0, 2.0 * dx);
  EXPECT_NEAR(near.area_mm2, 12.0 + 10.0 * 0.02, 2.0 * dx);
  EXPECT_EQ(Measure(test::Render(with_film(-14.5), {}, grid)).status, ProfileStatus::kBeadEdgeNotSeen);
}

// A spike is bridged on the chord of its neighbours, which adds exactly the
// trapezoids the neighbours' own segment would: a profile with spikes
// measures as the same profile with those points missing (NaN), to float
// rounding, wherever the spikes fall: single or in pairs, up or down, in
// the reference areas and on the bead, at any offset in the blocks the
// search goes by (most of the 640 positions are hit across the seeds).
// Groups stay three points apart, so no window of five holds three spike
// points (the definition's limit). A spike missed would add about
// spacing x 1 mm = 0.08 mm^2.
TEST(BeadGeometry, SpikesMeasureAsMissingPoints) {
  const auto clean = test::Render(sim::ParabolaOutline(9.0, 3.0), {0.02, 0.0, 40.0}, test::UniformGrid(640));
  std::vector<int> hit(clean.x.size(), 0);
  for (unsigned seed = 1; seed <= 60; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::size_t> where(3, clean.x.size() - 4);
    std::uniform_real_distribution<float> size(1.0f, 2.0f);
    auto spiked = clean, missing = clean;
    std::vector<bool> taken(clean.x.size(), false);
    for (int k = 0; k < 20; ++k) {
      const std::size_t i = where(rng);
      const std::size_t len = k % 4 == 0 ? 2 : 1;  // every fourth a pair
      bool free = true;
      for (std::size_t j = i - 3; j < std::min(i + len + 3, taken.size()); ++j) free = free && !taken[j];
      if (!free) continue;
      const float jump = (k % 3 == 0 ? -1.0f : 1.0f) * size(rng);
      for (std::size_t j = i; j < i + len; ++j) {
        taken[j] = true;
        ++hit[j];
        spiked.z[j] += jump;
        missing.z[j] = kNaN;
      }
    }
    const BeadGeometry a = Measure(spiked), b = Measure(missing);
    ASSERT_TRUE(a.valid() && b.valid()) << "seed " << seed;
    EXPECT_NEAR(a.area_mm2, b.area_mm2, 1e-5 * b.area_mm2) << "seed " << seed;
    EXPECT_NEAR(a.width_mm, b.width_mm, 1e-5 * b.width_mm) << "seed " << seed;
    EXPECT_EQ(a.dropped_points, b.dropped_points) << "seed " << seed;
  }
  EXPECT_GT(std::count_if(hit.begin() + 2, hit.end() - 4, [](int c) { return c > 0; }), 0.6 * (clean.x.size() - 6));
}

// A dropout shorter than max_gap_mm inside the bead is bridged, and the
// points it swallowed are counted.
TEST(BeadGeometry, ShortDropoutInsideBeadIsBridged) {
  auto p = test::Render(sim::RectangleOutline(8.0, 2.0), {}, test::UniformGrid(640));
  int removed = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (p.x[i] > 0.0 && p.x[i] < 0.6) {
      p.z[i] = kNaN;
      ++removed;
    }
  const BeadGeometry g = Measure(p);
  ASSERT_TRUE(g.valid());
  EXPECT_EQ(g.dropped_points, removed);
  EXPECT_NEAR(g.area_mm2, 16.0, 2.0 * p.spacing());  // the top is flat: bridging is exact
}

}  // namespace
}  // namespace bead
