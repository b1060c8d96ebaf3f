// The two builds of the per-profile kernel (kernel.h) compute the same
// geometry: they differ only in how sums are grouped and whether a
// multiply-add is fused, which moves a float's last bits (1e-5 relative on
// the results covers a few hundred roundings of 6e-8 each). Counts and
// statuses come from comparisons against thresholds far from the values
// here, so they agree exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "libbead/profile/kernel.h"
#include "tests/support/synthetic.h"

namespace bead {
namespace {

TEST(ProfileKernel, TheActiveOneIsTheWidestThisProcessorRuns) {
  const ProfileKernel* avx2 = Avx2Kernel();
  EXPECT_STREQ(ActiveKernel().name, avx2 ? "avx2" : "baseline");
  EXPECT_STREQ(BaselineKernel().name, "baseline");
}

TEST(ProfileKernel, BaselineAndAvx2Agree) {
  const ProfileKernel* avx2 = Avx2Kernel();
  if (!avx2) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  const ProfileKernel& base = BaselineKernel();
  sim::SensorNoise noise;
  noise.z_sigma_mm = 0.01;
  noise.dropout_prob = 0.03;
  noise.spike_prob = 0.01;
  noise.spike_mm = 2.0;
  const ProfileOptions options;
  int valid = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const double roll = (static_cast<int>(seed % 7) - 3) * std::numbers::pi / 180.0;
    const int points = seed % 2 ? 640 : 2048;
    const auto p = test::Render(sim::ParabolaOutline(6.0 + 0.1 * seed, 2.0 + 0.05 * seed, 0.1 * (seed % 5)),
                                {roll, 0.0, 40.0 + 0.01 * seed}, test::UniformGrid(points), noise, seed);
    ProfileWorkspace wa(p.x.size()), wb(p.x.size());
    const BeadGeometry a = base.process(p.view(), test::kLeft, test::kRight, options, wa);
    const BeadGeometry b = avx2->process(p.view(), test::kLeft, test::kRight, options, wb);
    ASSERT_EQ(a.status, b.status) << "seed " << seed;
    if (!a.valid()) continue;
    ++valid;
    EXPECT_NEAR(a.area_mm2, b.area_mm2, 1e-5 * a.area_mm2) << "seed " << seed;
    EXPECT_NEAR(a.width_mm, b.width_mm, 1e-5 * a.width_mm) << "seed " << seed;
    EXPECT_NEAR(a.height_mm, b.height_mm, 1e-5 * a.height_mm) << "seed " << seed;
    EXPECT_NEAR(a.center_x_mm, b.center_x_mm, 1e-5) << "seed " << seed;
    EXPECT_NEAR(a.reference.slope, b.reference.slope, 1e-6) << "seed " << seed;
    EXPECT_NEAR(a.reference.intercept_mm, b.reference.intercept_mm, 1e-5 * std::abs(a.reference.intercept_mm))
        << "seed " << seed;
    EXPECT_EQ(a.bead_points, b.bead_points) << "seed " << seed;
    EXPECT_EQ(a.dropped_points, b.dropped_points) << "seed " << seed;
    EXPECT_EQ(a.reference.points_used, b.reference.points_used) << "seed " << seed;
  }
  EXPECT_EQ(valid, 40);
}

}  // namespace
}  // namespace bead
