// The laser plane file: where the camera sees the laser plane, as point
// pairs of a calibration target in the laser's light (an extension of
// docs/data-formats.md, read by `bead frames --plane`):
//
//   points:            # four or more, not all on one line
//     - [u, v, x_mm, z_mm]   # pixel column and row -> position on the plane
//
// Errors name the file, the line and the key.
#pragma once

#include <string>

#include "libbead/vision/laser_plane.h"

namespace bead::vision {

LaserPlaneMap ReadLaserPlaneYaml(const std::string& path);

}  // namespace bead::vision
