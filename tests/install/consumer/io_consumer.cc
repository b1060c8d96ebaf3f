// Reads a rig file with the installed bead::io.
#include <cstdio>

#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  try {
    const bead::Rig rig = bead::ReadRig(argv[1]);
    std::printf("io: %s: reference areas [%g, %g] [%g, %g] mm\n", argv[1], rig.reference_left.x_min_mm,
                rig.reference_left.x_max_mm, rig.reference_right.x_min_mm, rig.reference_right.x_max_mm);
    return rig.reference_left.x_max_mm < rig.reference_right.x_min_mm ? 0 : 1;
  } catch (const bead::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
