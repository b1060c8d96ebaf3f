// The reference line is the bare wheel surface either side of the bead.
#include "libbead/profile/reference_line.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "tests/support/synthetic.h"

namespace bead {
namespace {

using test::kLeft;
using test::kRight;

ReferenceLine Fit(const test::Synthetic& p, const ReferenceLineOptions& o = {}) {
  ProfileWorkspace w(p.x.size());
  return FitReferenceLine(p.view(), kLeft, kRight, o, w);
}

// A sensor rolled by 3 degrees, 40 mm above a wheel whose runout lifts it
// 0.3 mm, sees the surface z = tan(roll) x + 40.3 (no bead in view).
TEST(ReferenceLine, RecoversRollAndRunoutExactlyWithoutNoise) {
  const double roll = 3.0 * M_PI / 180.0;
  const auto p = test::Render({}, {roll, 0.0, 40.3}, test::UniformGrid(640));
  const ReferenceLine line = Fit(p);
  ASSERT_TRUE(line.ok);
  // float32 coordinates: about 1e-7 relative on a 40 mm height.
  EXPECT_NEAR(line.slope, std::tan(roll), 1e-6);
  EXPECT_NEAR(line.intercept_mm, 40.3, 2e-5);
  EXPECT_LT(line.residual_rms_mm, 1e-5);
  EXPECT_EQ(line.points_used, line.points_available);
}

// With Gaussian noise sigma on n points spread over the two areas, the
// intercept error has standard deviation about sigma / sqrt(n) and the slope
// error sigma / (sqrt(n) * half distance between the areas).
// 20 % of the points are reflection spikes of 1-2 mm; 10 % are dropouts.
TEST(ReferenceLine, SurvivesTwentyPercentSpikesAndDropouts) {
  const double sigma = 0.01, roll = -0.04;
  sim::SensorNoise noise;
  noise.z_sigma_mm = sigma;
  noise.spike_prob = 0.2;
  noise.spike_mm = 2.0;
  noise.dropout_prob = 0.1;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const auto p = test::Render(sim::ParabolaOutline(8.0, 3.0), {roll, 0.0, 12.0}, test::UniformGrid(640), noise, seed);
    const ReferenceLine line = Fit(p);
    ASSERT_TRUE(line.ok) << "seed " << seed;
    const double n = line.points_used;
    EXPECT_GT(n, 0.6 * line.points_available);
    const double half_span = 18.0;  // area centres at -18 and +18 mm
    // 5 sigma bounds, with the float32 rounding far below them.
    EXPECT_NEAR(line.slope, std::tan(roll), 5 * sigma / (std::sqrt(n) * half_span)) << "seed " << seed;
    EXPECT_NEAR(line.intercept_mm, 12.0, 5 * sigma / std::sqrt(n)) << "seed " << seed;
    // The inliers' RMS is the noise, not the spikes.
    EXPECT_NEAR(line.residual_rms_mm, sigma, 0.25 * sigma) << "seed " << seed;
  }
}

// The robust start fails only when most of its triples are spoiled; with
// 20 % spikes and 5 % dropouts that must stay rare. A start that let the
// dropouts count as outliers and took the MAD from each area's 16 triples
// alone failed about once in 500 profiles (the band then swallows spikes:
// RMS 0.3 mm); over 3000 profiles it would show with probability
// 1 - exp(-6) = 0.998. A sound fit leaves these 5 sigma bounds with
// probability ~1e-6 each.
TEST(ReferenceLine, RobustStartHoldsOverThousandsOfProfiles) {
  const double sigma = 0.01;
  sim::SensorNoise noise;
  noise.z_sigma_mm = sigma;
  noise.spike_prob = 0.2;
  noise.spike_mm = 2.0;
  noise.dropout_prob = 0.05;
  std::vector<test::Synthetic> clean;  // rolls from -3 to +3 degrees
  for (int k = 0; k < 10; ++k)
    clean.push_back(test::Render(sim::ParabolaOutline(8.0, 3.0), {(k - 4.5) / 1.5 * M_PI / 180.0, 0.0, 12.0},
                                 test::UniformGrid(640)));
  int bad = 0;
  for (unsigned seed = 1; seed <= 3000; ++seed) {
    test::Synthetic p = clean[seed % clean.size()];
    std::mt19937_64 rng(seed);
    sim::AddSensorNoise(p.z, noise, rng);
    const ReferenceLine line = Fit(p);
    const double n = line.points_used;
    const bool ok = line.ok && std::abs(line.intercept_mm - 12.0) < 5 * sigma / std::sqrt(n) &&
                    std::abs(line.residual_rms_mm - sigma) < 0.25 * sigma;
    if (!ok)
      ++bad, ADD_FAILURE() << "seed " << seed << ": intercept " << line.intercept_mm << " rms " << line.residual_rms_mm;
  }
  EXPECT_EQ(bad, 0);
}

TEST(ReferenceLine, FailsWhenAnAreaHasTooFewPoints) {
  auto p = test::Render({}, {}, test::UniformGrid(640));
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (kRight.Contains(p.x[i])) p.z[i] = std::numeric_limits<float>::quiet_NaN();
  const ReferenceLine line = Fit(p);
  EXPECT_FALSE(line.ok);
  EXPECT_GT(line.points_available, 0);
}

// A point at height d above the line, measured perpendicular to it.
TEST(ReferenceLine, HeightIsPerpendicularDistance) {
  ReferenceLine line;
  line.intercept_mm = 1.0;
  line.slope = 1.0;  // 45 degrees
  EXPECT_NEAR(line.HeightAt(0.0, 1.0 + std::sqrt(2.0)), 1.0, 1e-12);
  EXPECT_NEAR(line.HeightAt(5.0, 6.0), 0.0, 1e-12);
}

}  // namespace
}  // namespace bead
