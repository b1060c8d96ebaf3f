// The twin's surfaces hold its beads on a grid (sim/laid_surface.h). A
// bead's shape must not depend on its size: a glue bead a tenth the
// twin's, seen by a sensor a tenth as coarse, is the twin's bead scaled.
// On a fixed 0.01 mm grid it was not: beside a bead's side, where its top
// falls as the square root of the distance to its end, the grid's chords
// lay up to 12 noises under the ellipse at a tenth of the twin's scale
// (3.7 at the twin's), and the shapes fitted to those sides came out
// 0.5 % small.
#include "libbead/sim/laid_surface.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bead::sim {
namespace {

// The twin's default bead (6 mm wide, aspect 0.5, 12 mm^2) laid on a flat
// bed, every length k times, on the grid a sensor of points 0.05 k apart
// asks for.
Surface Laid(double k, double* zc) {
  Surface bed;
  bed.dx = TruthGridMm(0.05 * k);
  bed.x0 = -6.0 * k;
  bed.z.assign(static_cast<std::size_t>(std::lround(12.0 * k / bed.dx)) + 1, 0.0);
  Layer bead;
  bead.area = 12.0 * k * k;
  bead.center = 0.37 * k;
  return Lay(bed, bead, 3.0 * k, 1.5 * k, zc);
}

TEST(LaidSurface, ABeadATenthTheTwinsSizeIsTheTwinsBeadScaled) {
  constexpr double k = 0.1;
  double zc1 = 0.0, zck = 0.0;
  const Surface twin = Laid(1.0, &zc1), small = Laid(k, &zck);
  EXPECT_NEAR(zck / k, zc1, 1e-9) << "the bead settles at the same depth";
  // Every 7 um of the twin's scale across the bead and past its sides:
  // the same height, scaled, to a nanometre (the grids' rounding, on the
  // sides' steep slopes).
  double worst = 0.0;
  for (double x = -4.0; x <= 4.0; x += 0.007) worst = std::max(worst, std::abs(small.At(k * x) / k - twin.At(x)));
  EXPECT_LT(worst, 1e-6) << "the small bead's surface, scaled, is the twin's";
}

}  // namespace
}  // namespace bead::sim
