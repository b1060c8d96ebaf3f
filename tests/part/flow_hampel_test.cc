// The flow along each layer's path filtered as the wheel's area is
// (part/flow_hampel.h): one row standing apart from a smooth flow takes its
// window's median; every other row, an invalid one and another layer's
// rows (whose flow is half the first's) pass as they came, in order.
#include "libbead/part/flow_hampel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace bead::part {
namespace {

TEST(FlowHampel, ARowStandingApartTakesItsWindowsMedianAndNothingElseMoves) {
  std::vector<PartFlowRow> in;
  for (int k = 0; k < 38; ++k) {
    PartFlowRow r;
    r.profile = k, r.layer = k < 30 ? 0 : 1, r.path_mm = 0.5 * k, r.valid = k != 5;
    r.flow_mm3_s = (k < 30 ? 100.0 : 50.0) + 0.5 * std::sin(k / 3.0);
    r.flow_sigma_mm3_s = 0.2;
    in.push_back(r);
  }
  in[12].flow_mm3_s += 20.0;  // a row where the layer below stepped
  FlowHampel filter;
  std::vector<PartFlowRow> out;
  const FlowHampel::Emit keep = [&](const PartFlowRow& r) { out.push_back(r); };
  for (const PartFlowRow& r : in) filter.Add(r, keep);
  filter.Flush(keep);
  ASSERT_EQ(out.size(), in.size());
  EXPECT_EQ(filter.replaced(), 1u);
  for (std::size_t k = 0; k < in.size(); ++k) {
    EXPECT_EQ(out[k].profile, in[k].profile);
    EXPECT_EQ(out[k].valid, in[k].valid);
    if (k == 12) {
      // The median of its window's eleven smooth flows (+-0.5 about 100).
      EXPECT_TRUE(out[k].flow_replaced);
      EXPECT_NEAR(out[k].flow_mm3_s, 100.0, 0.5);
    } else {
      EXPECT_FALSE(out[k].flow_replaced) << k;
      EXPECT_EQ(out[k].flow_mm3_s, in[k].flow_mm3_s) << k;
    }
  }
}

}  // namespace
}  // namespace bead::part
