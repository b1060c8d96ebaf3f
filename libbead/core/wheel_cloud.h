// A run's profiles as one point cloud in wheel coordinates: x across the
// bead (the sensor's x), s along the wheel's surface (from the encoder),
// z the height above the profile's reference line; and the sensor's own
// z beside it. A part scan's cloud (format 1.1) is in the bed frame: x
// across the path (x + frame_x_mm), s along the toolpath (path_mm), z the
// height above the bed (z + frame_z_mm), with each point's layer. Plain data: the
// archive stage makes it (archive/wheel_cloud_builder.h), io/ writes it as
// PLY or PCD (io/point_cloud.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bead {

struct WheelCloud {
  std::vector<float> x_mm;         // across the bead, the sensor's x
  std::vector<float> s_mm;         // along the surface, from the first profile's position
  std::vector<float> z_mm;         // perpendicular height above the profile's reference line
  std::vector<float> z_sensor_mm;  // the sensor's own z, as in the run (so the run comes back exactly)
  std::vector<uint32_t> profile;   // the profile's index in the run
  std::vector<double> t_s;         // the profile's time
  std::vector<int64_t> encoder;    // the profile's raw encoder reading (0: a part has none)
  std::vector<int64_t> layer;      // a part scan's layer of each point; empty for a run on the wheel

  std::size_t size() const { return x_mm.size(); }
};

}  // namespace bead
