/* Measures every profile of a profiles CSV (profile,t_s,encoder,x_mm,z_mm,
 * one row per point, a profile's rows together) through libbead's C
 * interface, and prints a row per profile:
 *   profile,area_mm2,width_mm,height_mm,center_x_mm,valid,status
 *
 *   measure_profiles LEFT_MIN LEFT_MAX RIGHT_MIN RIGHT_MAX profiles.csv
 *
 * Build against an installed libbead:
 *   cc measure_profiles.c $(pkg-config --cflags --libs bead) -o measure_profiles */
#include <bead/bead.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int flush(bead_processor* p, long id, const float* x, const float* z, size_t n) {
  bead_geometry g;
  if (bead_processor_measure(p, x, z, n, &g) != 0) {
    fprintf(stderr, "profile %ld: %s\n", id, bead_last_error());
    return -1;
  }
  printf("%ld,%.9g,%.9g,%.9g,%.9g,%d,%s\n", id, g.area_mm2, g.width_mm, g.height_mm, g.center_x_mm, g.valid,
         bead_status_name(g.status));
  return 0;
}

int main(int argc, char** argv) {
  if (argc != 6) {
    fprintf(stderr, "usage: %s LEFT_MIN LEFT_MAX RIGHT_MIN RIGHT_MAX profiles.csv\n", argv[0]);
    return 2;
  }
  const double left[2] = {atof(argv[1]), atof(argv[2])}, right[2] = {atof(argv[3]), atof(argv[4])};
  bead_processor* p = bead_processor_create(left, right);
  if (!p) {
    fprintf(stderr, "%s\n", bead_last_error());
    return 1;
  }
  FILE* f = fopen(argv[5], "r");
  if (!f) {
    perror(argv[5]);
    return 1;
  }
  char line[512];
  size_t n = 0, cap = 1024;
  float* x = malloc(cap * sizeof *x);
  float* z = malloc(cap * sizeof *z);
  long current = -1, row = 0;
  int status = 0;
  printf("profile,area_mm2,width_mm,height_mm,center_x_mm,valid,status\n");
  if (!fgets(line, sizeof line, f)) { /* the header */
    fprintf(stderr, "%s: empty\n", argv[5]);
    return 1;
  }
  while (fgets(line, sizeof line, f)) {
    ++row;
    /* Five fields; an empty one is NaN (a dropout's z). */
    char* field[5];
    int k = 0;
    for (char* c = line; k < 5; ++k) {
      field[k] = c;
      char* comma = strchr(c, ',');
      if (!comma) {
        ++k;
        break;
      }
      *comma = '\0';
      c = comma + 1;
    }
    if (k != 5) {
      fprintf(stderr, "%s: row %ld: expected profile,t_s,encoder,x_mm,z_mm\n", argv[5], row + 1);
      return 1;
    }
    const long id = atol(field[0]);
    const double xv = field[3][0] && field[3][0] != '\n' ? atof(field[3]) : NAN;
    const double zv = field[4][0] && field[4][0] != '\n' && field[4][0] != '\r' ? atof(field[4]) : NAN;
    if (id != current && current >= 0) {
      if (flush(p, current, x, z, n) != 0) status = 1;
      n = 0;
    }
    current = id;
    if (n == cap) {
      cap *= 2;
      x = realloc(x, cap * sizeof *x);
      z = realloc(z, cap * sizeof *z);
    }
    x[n] = (float)xv;
    z[n] = (float)zv;
    ++n;
  }
  if (current >= 0 && flush(p, current, x, z, n) != 0) status = 1;
  fclose(f);
  free(x);
  free(z);
  bead_processor_destroy(p);
  return status;
}
