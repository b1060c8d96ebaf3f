// A run archive from camera frames of the stripe: each frame's profile on
// the laser plane (frame_profile.h), one a frame at `rate_hz`, no encoder
// (the archive says so: docs/data-formats.md). The stripe's axis is the
// sensor's, or the first frame's when auto: one axis for the run.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libbead/io/run_archive.h"
#include "libbead/vision/sensor.h"
#include "libbead/vision/stripe.h"

namespace bead::vision {

struct FramesRun {
  RunArchive run;
  StripeOptions stripe;    // as used (the axis resolved)
  StripeStats total;       // over every frame
  std::size_t lines = 0;   // profile points per frame (the image's columns or rows)
  std::size_t points = 0;  // stripe points found in all
};

// Throws bead::Error naming the frame that cannot be read, has no usable
// stripe geometry, or differs in size from the first. `progress`: (frames
// read, frames).
FramesRun RunFromFrames(const std::vector<std::string>& paths, SensorModel sensor, double rate_hz,
                        const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace bead::vision
