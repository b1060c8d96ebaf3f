// The batch path runs the streaming processor: results are identical, and
// splitting over threads changes nothing.
#include "libbead/profile/measure_block.h"

#include <gtest/gtest.h>

#include "tests/support/synthetic.h"

namespace bead {
namespace {

TEST(MeasureProfiles, ThreadsGiveTheSameResultsAsOneProcessor) {
  sim::SensorNoise noise;
  noise.z_sigma_mm = 0.02;
  noise.dropout_prob = 0.05;
  std::vector<test::Synthetic> profiles;
  for (unsigned i = 0; i < 2000; ++i)
    profiles.push_back(test::Render(sim::ParabolaOutline(6.0 + (i % 7), 2.0), {0.01, 0.0, 40.0 + 0.001 * i},
                                    test::UniformGrid(320), noise, i));
  auto view = [&](std::size_t i) { return profiles[i].view(); };
  BlockOptions two;
  two.threads = 2;
  const auto batch = MeasureProfiles(profiles.size(), view, test::kLeft, test::kRight, {}, two);
  ProfileProcessor one(test::kLeft, test::kRight);
  ASSERT_EQ(batch.size(), profiles.size());
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    const BeadGeometry& g = one.Process(view(i));
    EXPECT_EQ(batch[i].status, g.status);
    EXPECT_EQ(batch[i].area_mm2, g.area_mm2) << i;
    EXPECT_EQ(batch[i].width_mm, g.width_mm) << i;
  }
}

}  // namespace
}  // namespace bead
