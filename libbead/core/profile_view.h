// ProfileView: one laser-line profile as the sensor reported it, borrowed
// (no copy). Coordinates follow the run archive format (docs/data-formats.md): x along the
// laser line, z height growing toward the sensor, both mm; NaN where the
// sensor measured nothing. x may be non-uniform, decreasing or unsorted.
#pragma once

#include <cstdint>
#include <span>

namespace bead {

struct ProfileView {
  std::span<const float> x_mm;
  std::span<const float> z_mm;  // same length as x_mm
  double t_s = 0.0;             // time the profile was measured
  int64_t encoder = 0;          // raw wheel counter at that time
};

}  // namespace bead
