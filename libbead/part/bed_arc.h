// The bed of a first layer laid along a pipe (the rig file's part: {bed:
// cylinder}): the arc through the bare surface either side of the bead,
// z = zc + sqrt(R^2 - (x - xc)^2), its centre fitted and its radius too
// when the rig gives none. The bead may wander off the crest onto the
// slope: the arc, not a line, is what it was laid on.
//
// Method: the points of the profile's two reference areas; a start from
// the algebraic circle (Kasa: x^2 + z^2 + D x + E z + F = 0, linear least
// squares), then Gauss-Newton on the geometric distances |p - c| - R; the
// points beyond 3.5 robust sigmas (1.4826 MAD) of that fit dropped and the
// fit made again.
#pragma once

#include <span>
#include <string>

#include "libbead/core/rig.h"

namespace bead::part {

struct BedArc {
  bool ok = false;
  double xc_mm = 0.0, zc_mm = 0.0, radius_mm = 0.0;  // the profile's frame
  double rms_mm = 0.0;                               // geometric residual of the points used
  int points = 0;
  std::string why;               // when not ok
  double At(double x_mm) const;  // NaN beyond the circle's width
};

// radius_mm > 0: held at that radius; 0: fitted.
BedArc FitBedArc(std::span<const float> x, std::span<const float> z, const ReferenceArea& left,
                 const ReferenceArea& right, double radius_mm);

}  // namespace bead::part
