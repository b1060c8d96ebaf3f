// The sensor file (docs/data-formats.md, "Sensor file"), written by
// `bead calibrate laser` and read by `bead frames --sensor`:
//
//   camera:
//     matrix: [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]   # px
//     distortion: [k1, k2, p1, p2, k3]
//     image_size: [width, height]                     # px
//   laser:
//     plane: [a, b, c, d]       # a x + b y + c z + d = 0, camera coordinates, mm
//     homography: [[...], [...], [...]]   # undistorted pixel -> (x_mm, z_mm) on the plane
//   stripe: {axis: rows|columns, method: cog|gaussian|parabolic|steger,
//            threshold: 0, min_peak: 20, min_width_px: 1, max_width_px: 40, rule: strongest}
//
// `stripe` and its keys are optional (the defaults of stripe.h); any
// other top-level key (`calibration`, the figures of the calibration that
// made it) is kept for the reader and ignored. Errors name the file, the
// line and the key.
#pragma once

#include <string>

#include "libbead/vision/sensor.h"

namespace bead::vision {

SensorModel ReadSensorYaml(const std::string& path);

// Written atomically; `notes` (a YAML mapping, may be empty) goes under
// the key `calibration`.
void WriteSensorYaml(const std::string& path, const SensorModel& sensor, const std::string& notes_yaml);

}  // namespace bead::vision
