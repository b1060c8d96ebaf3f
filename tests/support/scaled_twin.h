// A part twin's configuration at another size: every length (and the
// noise) k times, areas k^2 times, the displacement per screw turn k^3
// times, speeds and accelerations k times so every time stays as it was.
// The same part, so every figure should hold as at k = 1 (the part tests'
// large-scale and glue-bead walls and roads).
#pragma once

#include "libbead/sim/part_twin.h"

namespace bead::test {

inline sim::PartTwinConfig Scaled(sim::PartTwinConfig c, double k) {
  for (double* length : {&c.contour_length_mm,
                         &c.contour_width_mm,
                         &c.corner_radius_mm,
                         &c.length_mm,
                         &c.head_speed_mm_s,
                         &c.lateral_accel_mm_s2,
                         &c.tangential_accel_mm_s2,
                         &c.profile_spacing_mm,
                         &c.trail_mm,
                         &c.width_mm,
                         &c.wave_period_mm,
                         &c.wander_sigma_mm,
                         &c.wander_wave_mm,
                         &c.wander_wave_period_mm,
                         &c.pass_shift_sigma_mm,
                         &c.frame_x_wave_mm,
                         &c.standoff_mm,
                         &c.noise_mm,
                         &c.shadow_mm,
                         &c.point_spacing_mm,
                         &c.field_half_mm,
                         &c.bed_radius_mm,
                         &c.road_spacing_mm})
    *length *= k;
  c.area_mm2 *= k * k, c.area_wave_mm2 *= k * k;
  c.displacement_mm3_per_rev *= k * k * k;
  return c;
}

}  // namespace bead::test
