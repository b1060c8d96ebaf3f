/* The same parabolic bead through the C interface of the installed
 * libbead.so. */
#include <bead/bead.h>
#include <math.h>
#include <stdio.h>

int main(void) {
  float x[1001], z[1001];
  for (int i = 0; i <= 1000; ++i) {
    const double xi = -25.0 + 0.05 * i, t = (xi - 0.3) / 3.0;
    x[i] = (float)xi;
    z[i] = (float)(fabs(t) < 1 ? 2.0 * (1 - t * t) : 0.0);
  }
  const double left[2] = {-24, -12}, right[2] = {12, 24};
  bead_processor* p = bead_processor_create(left, right);
  if (!p) {
    fprintf(stderr, "%s\n", bead_last_error());
    return 1;
  }
  bead_geometry g;
  if (bead_processor_measure(p, x, z, 1001, &g) != 0) return 1;
  printf("c (libbead %s): area %.6f mm^2 %s\n", bead_version(), g.area_mm2, bead_status_name(g.status));
  bead_processor_destroy(p);
  return g.valid && fabs(g.area_mm2 - 8.0) < 1e-3 ? 0 : 1;
}
