// Property: for any bead the sensor can see whole (no overhang at its
// roll), on any grid, the measured area is within H * (largest spacing) of
// the exact area, and the width within two spacings.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libbead/profile/profile_processor.h"
#include "tests/support/synthetic.h"

namespace bead {
namespace {

TEST(BeadGeometryProperty, RandomShapesRollsAndGrids) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double height = 0.5 + 5.0 * u(rng);
    const double width = 3.0 + 14.0 * u(rng);
    const double center = (u(rng) - 0.5) * (22.0 - width);
    const double roll = (u(rng) - 0.5) * 6.0 * M_PI / 180.0;  // within +-3 degrees
    const int points = 200 + static_cast<int>(1848 * u(rng));
    sim::Outline outline;
    double area;
    if (trial % 2 == 0) {
      outline = sim::ParabolaOutline(width, height, center);
      area = 2.0 * width * height / 3.0;
    } else {
      // Walls no steeper than atan(10) = 84 degrees: no shadow at 3 degrees roll.
      const double top = width - std::max(0.2 * height, 0.05 * width) - 0.8 * width * u(rng);
      outline = sim::TrapezoidOutline(width, std::max(top, 0.0), height, center);
      area = (width + std::max(top, 0.0)) * height / 2.0;
    }
    // The sensor's x offset moves the bead, but not into a reference area.
    const double margin = 11.0 - width / 2 - std::abs(center);
    const double x_offset = (u(rng) - 0.5) * 1.8 * margin;
    const auto p = test::Render(outline, {roll, x_offset, 20.0 + 40.0 * u(rng)}, test::UniformGrid(points));
    const BeadGeometry g = MeasureProfile(p.view(), test::kLeft, test::kRight);
    ASSERT_TRUE(g.valid()) << "trial " << trial << ": " << StatusName(g.status);
    const double dx = p.spacing();
    EXPECT_NEAR(g.area_mm2, area, height * dx) << "trial " << trial;
    EXPECT_NEAR(g.width_mm, width, 2 * dx) << "trial " << trial;
    ++checked;
  }
  EXPECT_EQ(checked, 300);
}

}  // namespace
}  // namespace bead
