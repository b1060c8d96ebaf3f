// The wheel coordinates of a run's points (core/wheel_cloud.h). Each
// profile's reference line comes from the same ProfileProcessor as `bead
// measure`'s; z is the perpendicular height above it (ReferenceLine::
// HeightAt), x stays the sensor's x so that the rig's reference areas
// still hold for the cloud read back. s is the surface travel of the
// unwrapped encoder (thesis 3.1: pi D / counts per revolution per count)
// from the first profile; a run without encoder readings needs a surface
// speed instead (s = v t).
#pragma once

#include <cstddef>
#include <string>

#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/core/wheel_cloud.h"
#include "libbead/profile/profile_processor.h"

namespace bead {

struct WheelCloudOptions {
  ProfileOptions profile;
  std::size_t every = 1;            // keep every this-many-th profile
  double surface_speed_mm_s = 0.0;  // > 0: s = v (t - t0) instead of the encoder
};

struct WheelCloudCount {
  std::size_t profiles = 0;      // profiles kept (every `every`-th)
  std::size_t no_reference = 0;  // of them, left out: no reference line to stand on
  std::size_t points = 0;        // finite points written
};

// Throws bead::Error naming `path` when the run has no encoder readings
// (`encoder_absent`) and no surface speed is given, or holds no profile.
WheelCloud BuildWheelCloud(const ProfileBlock& profiles, bool encoder_absent, const Rig& rig,
                           const WheelCloudOptions& options, const std::string& path, WheelCloudCount* count);

}  // namespace bead
