// Measures a parabolic bead (W 6 mm, H 2 mm: area 2 W H / 3 = 8 mm^2)
// sampled every 0.05 mm with the installed bead::core; the parabola is
// measured exactly (libbead's edge model), so the area must be 8 to float
// rounding.
#include <cmath>
#include <cstdio>
#include <vector>

#include "libbead/profile/profile_processor.h"

int main() {
  std::vector<float> x, z;
  for (int i = 0; i <= 1000; ++i) {
    const double xi = -25.0 + 0.05 * i, t = (xi - 0.3) / 3.0;
    x.push_back(static_cast<float>(xi));
    z.push_back(static_cast<float>(std::abs(t) < 1 ? 2.0 * (1 - t * t) : 0.0));
  }
  bead::ProfileProcessor p({-24, -12}, {12, 24});
  const bead::BeadGeometry& g = p.Process(bead::ProfileView{x, z, 0.0, 0});
  std::printf("core: area %.6f mm^2 width %.6f mm %s\n", g.area_mm2, g.width_mm, bead::StatusName(g.status));
  return g.valid() && std::abs(g.area_mm2 - 8.0) < 1e-3 && std::abs(g.width_mm - 6.0) < 1e-3 ? 0 : 1;
}
