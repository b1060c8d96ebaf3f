// Bead cross-section families with rounded corners and undercut, as dense
// polygons (see outline.h), scaled to a given area. The truth of a
// simulated bead is the area of exactly the polygon the sensor is shown.
//  - rounded rectangle: width W = aspect H; bottom corners of radius
//    rb = bottom_radius_frac H curl in under the widest point to a contact
//    width W - 2 rb (the undercut a sensor above cannot see: (1 - pi/4) rb^2
//    per corner); top corners of radius rt.
//    area = W H - (1 - pi/4) (2 rb^2 + 2 rt^2)
//  - superellipse |x/a|^n + |(y - c)/b|^n <= 1 cut by the surface y = 0,
//    centre lifted c = center_lift_frac b: contact narrower than the max width;
//    with bottom_exponent set, the part below the widest point has its own
//    exponent (the hidden half is then not the mirror of the seen half).
//  - parabola of width aspect H (no undercut).
#pragma once

#include "libbead/sim/outline.h"
#include "libbead/sim/sim_config.h"

namespace bead::sim {

struct BeadDims {
  double max_width_mm = 0, contact_width_mm = 0, height_mm = 0;
};

// The family's outline at height 1, centred on s = 0.
Outline UnitBeadOutline(const BeadConfig& config);

// Scales a unit outline (whose polygon area is unit_area) to `area_mm2`, centred on `center_mm`.
Outline ScaledOutline(const Outline& unit, double unit_area, double area_mm2, double center_mm);

BeadDims OutlineDims(const Outline& outline);

}  // namespace bead::sim
