#include "libbead/part/part_cloud.h"

#include <cmath>

namespace bead::part {

WheelCloud BuildPartCloud(const ProfileBlock& profiles, const PartPlaces& places, std::size_t every) {
  WheelCloud c;
  for (std::size_t i = 0; i < profiles.size(); i += std::max<std::size_t>(every, 1)) {
    const ProfileView v = profiles.view(i);
    for (std::size_t j = 0; j < v.x_mm.size(); ++j) {
      if (!std::isfinite(v.x_mm[j]) || !std::isfinite(v.z_mm[j])) continue;
      c.x_mm.push_back(static_cast<float>(v.x_mm[j] + places.frame_x_mm[i]));
      c.s_mm.push_back(static_cast<float>(places.path_mm[i]));
      c.z_mm.push_back(static_cast<float>(v.z_mm[j] + places.frame_z_mm[i]));
      c.z_sensor_mm.push_back(v.z_mm[j]);
      c.profile.push_back(static_cast<uint32_t>(i));
      c.t_s.push_back(v.t_s);
      c.encoder.push_back(0);
      c.layer.push_back(places.layer[i]);
    }
  }
  return c;
}

}  // namespace bead::part
