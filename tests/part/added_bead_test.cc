// The scales a part profile is measured in (part/added_bead.h): its noise
// from second differences and its points' spacing, each found without
// sorting where it can be, and the same as the sorted definition.
#include "libbead/part/added_bead.h"
#include "libbead/part/part_kernel.h"
#include "libbead/part/surface_below.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace bead::part {
namespace {

// The definition: 1.4826 median |z_i - 2 z_i+1 + z_i+2| / sqrt 6, at least 0.002.
double SortedNoise(const std::vector<float>& z) {
  std::vector<float> second;
  for (std::size_t i = 0; i + 2 < z.size(); ++i)
    second.push_back(static_cast<float>(std::abs(z[i] - 2.0 * z[i + 1] + z[i + 2])));
  std::nth_element(second.begin(), second.begin() + static_cast<std::ptrdiff_t>(second.size() / 2), second.end());
  return std::max(0.002, 1.4826 * second[second.size() / 2] / std::sqrt(6.0));
}

TEST(AddedBead, TheNoiseIsTheSortedMediansWhateverTheProfileBefore) {
  std::mt19937 rng(5);
  // Runs of profiles at one noise (the median found near the one
  // before's), then a jump (found by sorting them all), over a bead.
  for (double sigma : {0.01, 0.01, 0.011, 0.03, 0.03, 0.004, 0.02, 0.02, 0.02}) {
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<float> z;
    for (int j = 0; j < 801; ++j) {
      const double x = -20.0 + 0.05 * j;
      z.push_back(static_cast<float>((std::abs(x) < 3.0 ? std::sqrt(9.0 - x * x) : 0.0) + noise(rng)));
    }
    // The second differences are taken in floats (each difference of
    // neighbours first), the definition's in doubles: each value within
    // two float roundings (2.4e-7 of it), and so their median.
    EXPECT_NEAR(ProfileNoiseMm(z), SortedNoise(z), 2.4e-7 * SortedNoise(z)) << sigma;
  }
}

TEST(AddedBead, BothBuildsBandTheValuesAsCountedOneByOne) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()})
    for (std::size_t n : {std::size_t{0}, std::size_t{7}, std::size_t{8}, std::size_t{801}}) {
      std::vector<float> v(n), band(n + 8);
      for (float& x : v) x = u(rng);
      std::size_t below = 0;
      const std::size_t in = kernel->band(v.data(), n, 0.3f, 0.55f, band.data(), below);
      std::vector<float> want;
      std::size_t want_below = 0;
      for (float x : v) {
        if (x >= 0.3f && x < 0.55f) want.push_back(x);
        want_below += x < 0.3f;
      }
      EXPECT_EQ(below, want_below) << kernel->name << " " << n;
      ASSERT_EQ(in, want.size()) << kernel->name << " " << n;
      EXPECT_TRUE(std::equal(want.begin(), want.end(), band.begin())) << kernel->name << " " << n;
    }
}

TEST(AddedBead, BothBuildsFindTheKthSmallestAsSortingDoes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()})
    for (std::size_t n : {1u, 7u, 64u, 65u, 128u, 129u, 300u}) {
      std::vector<float> v(n);
      for (float& x : v) x = u(rng);
      v[n / 2] = v[0];  // a tie
      std::vector<float> sorted = v;
      std::sort(sorted.begin(), sorted.end());
      for (std::size_t k : {std::size_t{0}, n / 2, n - 1}) {
        std::vector<float> w = v;
        EXPECT_EQ(kernel->kth(w.data(), n, k), sorted[k]) << kernel->name << " n " << n << " k " << k;
      }
    }
}

TEST(AddedBead, TheSpacingIsTheMedianStepWithOrWithoutSorting) {
  std::vector<float> x;
  for (int j = 0; j < 401; ++j)
    if (j % 9 != 4) x.push_back(static_cast<float>(-10.0 + 0.05 * j));  // one in nine missing
  // Most steps one spacing: found without sorting, within a thousandth.
  EXPECT_NEAR(PointSpacingMm(x), 0.05, 5e-5);
  // Steps of three lengths in turn, none more than a third: the sorted median.
  std::vector<float> uneven{0.0f};
  for (int j = 0; j < 99; ++j) uneven.push_back(uneven.back() + static_cast<float>(0.1 + 0.05 * (j % 3)));
  EXPECT_NEAR(PointSpacingMm(uneven), 0.15, 1e-6);
}

// A bead of 0.8 mm high and 6 mm wide (an ellipse) at x = 0 over a row
// of the layer below on the grid of 0.05 mm from -10 to 10 mm, the row's
// height at x `below`, the row's values and the bead's points each with
// the normal noise `sigma` (none where 0).
constexpr int kPoints = 401;
constexpr double kPointDx = 0.05, kX0 = -10.0;

struct BeadOverRow {
  SurfaceRow row;
  std::vector<float> x, z;
};

template <class Below>
BeadOverRow EllipseOver(Below below, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, std::max(sigma, 1e-300));
  const auto draw = [&] { return sigma > 0.0 ? noise(rng) : 0.0; };
  BeadOverRow b;
  b.row.x0_mm = kX0, b.row.dx_mm = kPointDx, b.row.at_points = true;
  for (int j = 0; j < kPoints; ++j) {
    const double xj = kX0 + kPointDx * j, u = xj / 3.0, bead = std::abs(u) < 1.0 ? 0.8 * std::sqrt(1.0 - u * u) : 0.0;
    b.row.z_mm.push_back(static_cast<float>(below(xj) + draw()));
    b.row.variance.push_back(1.0f);
    b.x.push_back(static_cast<float>(xj)), b.z.push_back(static_cast<float>(below(xj) + bead + draw()));
  }
  return b;
}

// The bead over a sloped line: its points' gains read in place where the
// surface below is known at every point between the first and the last
// that have it, and copied out where it is lost under some
// (part/added_bead.cc: GainsAt). The profile over a surface below lost
// under some of its points measures as the profile without them over the
// surface known everywhere: the same points, the same gains, the same bead.
TEST(AddedBead, PointsOverALostSurfaceBelowMeasureAsThePointsLeftOut) {
  std::mt19937 rng(7);
  const BeadOverRow b = EllipseOver([](double x) { return 1.0 + 0.01 * x; }, 0.01, rng);
  const SurfaceRow& full = b.row;
  const std::vector<float>& x = b.x;
  const std::vector<float>& z = b.z;
  SurfaceRow holed = full;
  std::vector<float> x_left, z_left;
  for (int j = 0; j < kPoints; ++j) {
    // Lost under points 150-154, on the bead's left flank; point 149 with
    // them (the surface below is linear between two values: NaN next to a
    // NaN, part/surface_below.h).
    if (j >= 150 && j < 155) holed.z_mm[j] = NAN;
    if (j < 149 || j >= 155) x_left.push_back(x[j]), z_left.push_back(z[j]);
  }
  const double spacing = kPointDx, noise_mm = 0.01;
  const AddedBead over_hole = MeasureAddedBead(x, z, SurfaceGrid(holed), false, {}, nullptr, spacing, 0.0, noise_mm);
  const AddedBead left_out =
      MeasureAddedBead(x_left, z_left, SurfaceGrid(full), false, {}, nullptr, spacing, 0.0, noise_mm);
  ASSERT_EQ(over_hole.status, AddedStatus::kValid);
  ASSERT_EQ(left_out.status, AddedStatus::kValid);
  EXPECT_EQ(over_hole.area_mm2, left_out.area_mm2);
  EXPECT_EQ(over_hole.width_mm, left_out.width_mm);
  EXPECT_EQ(over_hole.height_mm, left_out.height_mm);
  EXPECT_EQ(over_hole.center_x_mm, left_out.center_x_mm);
  // And both the bead's: pi a b / 2 = 3.77 mm^2 within the trapezoid's
  // sampling across the gap and the noise (0.01 mm over 6 mm: 0.02 mm^2).
  EXPECT_NEAR(left_out.area_mm2, 0.5 * M_PI * 3.0 * 0.8, 0.05);
}

// A bead's side falls toward its foot; a gain that rises again past a bare
// point beside it is something else: the layer below's wall beside the
// bead's end, interpolated across its cell by a registration a fraction of
// a spacing off, a wall's height off at one point. The bead measures as if
// that point were bare: its area to the floor's sliver (the point counted
// at the floor, 0.02 mm, over half a spacing), its width to a spacing.
TEST(AddedBead, AGainRisingAgainBesideTheBeadIsNotTheBeads) {
  constexpr double kNoise = 0.01;  // floor max(0.01, 2 noises) = 0.02 mm
  std::mt19937 rng(1);
  BeadOverRow b = EllipseOver([](double) { return 1.0; }, 0.0, rng);
  const SurfaceRow& flat = b.row;
  const std::vector<float>& x = b.x;
  std::vector<float>& z = b.z;
  const int end = 260;  // x = 3.00: the bead's right end, its gain 0 ...
  z[end] += 0.03f;      // ... raised over the floor, under the threshold (0.06)
  SurfaceRow walled = flat;
  walled.z_mm[end + 1] = -1.0f;  // the next point's gain 2 mm: the wall beside it
  const AddedBead bare = MeasureAddedBead(x, z, SurfaceGrid(flat), false, {}, nullptr, kPointDx, 0.0, kNoise);
  const AddedBead walled_off = MeasureAddedBead(x, z, SurfaceGrid(walled), false, {}, nullptr, kPointDx, 0.0, kNoise);
  ASSERT_EQ(bare.status, AddedStatus::kValid);
  ASSERT_EQ(walled_off.status, AddedStatus::kValid);
  EXPECT_NEAR(walled_off.area_mm2, bare.area_mm2, 0.5 * 0.02 * kPointDx + 1e-9);
  EXPECT_NEAR(walled_off.width_mm, bare.width_mm, kPointDx);
  EXPECT_EQ(walled_off.height_mm, bare.height_mm);
}

// A tamped bead's top is flat (part/superellipse.h: a stadium, half-round
// ends of radius r): its highest point lies anywhere on the flat, 4 mm of
// it here, and a parabola about that point has no vertex to give. The
// centre is the middle of the top, where its two ends fall to the same
// height. Twenty such beads at 30 um of noise, each placed a random
// fraction of a spacing off the grid: the level where the centre is read
// (a quarter of the height below the top, by the rule: half the lesser
// drop to a foot) lies on each end's arc where it rises 1.33 mm a mm, so
// each crossing moves by about the noise over that slope, 0.023 mm, and
// their middle by less: the RMS within twice that. (The parabola's vertex
// about the highest point: 1.1 mm off, median, on a generator's tamped
// walls.)
TEST(AddedBead, AFlatToppedBeadsCentreIsTheMiddleOfItsTop) {
  constexpr double kNoise = 0.03, kHalf = 3.0, kRadius = 1.0;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kNoise);
  std::uniform_real_distribution<double> place(-0.5, 0.5);
  SurfaceRow bed;
  bed.x0_mm = kX0, bed.dx_mm = kPointDx, bed.at_points = true;
  bed.z_mm.assign(kPoints, 0.0f), bed.variance.assign(kPoints, 1.0f);
  double sum2 = 0.0;
  constexpr int kBeads = 20;
  for (int k = 0; k < kBeads; ++k) {
    const double centre = place(rng);
    std::vector<float> x, z;
    for (int j = 0; j < kPoints; ++j) {
      const double xj = kX0 + kPointDx * j, v = std::abs(xj - centre) - (kHalf - kRadius);
      const double top = v <= 0.0 ? 2.0 * kRadius : v < kRadius ? kRadius + std::sqrt(kRadius * kRadius - v * v) : 0.0;
      x.push_back(static_cast<float>(xj)), z.push_back(static_cast<float>(top + noise(rng)));
    }
    const AddedBead b = MeasureAddedBead(x, z, SurfaceGrid(bed), false, {}, nullptr, kPointDx, 0.0, kNoise);
    ASSERT_EQ(b.status, AddedStatus::kValid) << k;
    sum2 += (b.center_x_mm - centre) * (b.center_x_mm - centre);
  }
  EXPECT_LT(std::sqrt(sum2 / kBeads), 2.0 * kNoise / 1.33);
}

}  // namespace
}  // namespace bead::part

namespace bead::part {
namespace {

// A layer only adds material: a new surface lying under the one before it
// by the threshold over more points than stand over it, and over a tenth
// of them, is two scans not where their frames say (a frame height missing
// or wrong), and is not measured; by how much it lies under is said (the
// median of those points: the frame's error, to the noise). A bead on the
// right frame, and a layer where nothing was laid, are what they were: the
// threshold (six noises of the point, its gain's two noises at 4.2 sigmas)
// leaves the noise's tails under it at 1e-5 of the points.
TEST(AddedBead, ASurfaceUnderTheOneBeforeItIsNotMeasured) {
  constexpr double kNoise = 0.01;
  for (const double drop : {2.0, 0.2, 0.0}) {
    std::mt19937 rng(11);
    BeadOverRow b = EllipseOver([](double x) { return 1.0 + 0.01 * x; }, kNoise, rng);
    for (float& z : b.z) z -= static_cast<float>(drop);
    const AddedBead m = MeasureAddedBead(b.x, b.z, SurfaceGrid(b.row), false, {}, nullptr, kPointDx, 0.0, kNoise);
    if (drop == 0.0) {
      EXPECT_EQ(m.status, AddedStatus::kValid);
      EXPECT_TRUE(std::isnan(m.under_mm));
      continue;
    }
    EXPECT_EQ(m.status, AddedStatus::kUnderSurfaceBelow) << drop;
    EXPECT_STREQ(AddedStatusName(m.status), "under_surface_below");
    // (The bead's own points under the threshold are its last 2 % of a
    // half-width a side at a drop of 0.2: a few of the 300 the median is of.)
    EXPECT_NEAR(m.under_mm, -drop, kNoise) << drop;
    EXPECT_TRUE(std::isnan(m.area_mm2));
  }
  std::mt19937 rng(12);
  BeadOverRow bare = EllipseOver([](double) { return 1.0; }, kNoise, rng);
  std::normal_distribution<double> noise(0.0, kNoise);
  for (int j = 0; j < kPoints; ++j) bare.z[j] = static_cast<float>(1.0 + noise(rng));
  const AddedBead none =
      MeasureAddedBead(bare.x, bare.z, SurfaceGrid(bare.row), false, {}, nullptr, kPointDx, 0.0, kNoise);
  EXPECT_EQ(none.status, AddedStatus::kNoBead);
}

}  // namespace
}  // namespace bead::part
