#include "libbead/archive/wheel_cloud_builder.h"

#include <cmath>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/series/encoder.h"

namespace bead {

WheelCloud BuildWheelCloud(const ProfileBlock& profiles, bool encoder_absent, const Rig& rig,
                           const WheelCloudOptions& options, const std::string& path, WheelCloudCount* count) {
  if (profiles.size() == 0) throw Error(Located(path, "/profiles", "holds no profile"));
  if (options.every == 0) throw Error(Located(path, "", "keep every 1st profile or more (every = 0)"));
  const bool by_speed = options.surface_speed_mm_s > 0.0;
  if (encoder_absent && !by_speed)
    throw Error(Located(path, "/profiles/encoder",
                        "the run has no encoder readings (encoder=absent): give the surface speed to place s = v t"));
  std::vector<double> counts;
  if (!by_speed) counts = UnwrapEncoder(profiles.encoder, rig.encoder, profiles.t_s).counts;

  WheelCloudCount n;
  WheelCloud cloud;
  ProfileProcessor processor(rig.reference_left, rig.reference_right, options.profile, profiles.points);
  for (std::size_t i = 0; i < profiles.size(); i += options.every) {
    ++n.profiles;
    const ProfileView view = profiles.view(i);
    const ReferenceLine line = processor.Process(view).reference;
    if (!line.ok) {
      ++n.no_reference;
      continue;
    }
    const double s = by_speed ? options.surface_speed_mm_s * (profiles.t_s[i] - profiles.t_s[0])
                              : CountsToMm(counts[i] - counts[0], rig);
    for (std::size_t k = 0; k < view.z_mm.size(); ++k) {
      const float x = view.x_mm[k], z = view.z_mm[k];
      if (!std::isfinite(x) || !std::isfinite(z)) continue;
      cloud.x_mm.push_back(x);
      cloud.s_mm.push_back(static_cast<float>(s));
      cloud.z_mm.push_back(static_cast<float>(line.HeightAt(x, z)));
      cloud.z_sensor_mm.push_back(z);
      cloud.profile.push_back(static_cast<uint32_t>(i));
      cloud.t_s.push_back(profiles.t_s[i]);
      cloud.encoder.push_back(profiles.encoder[i]);
    }
  }
  n.points = cloud.size();
  if (count) *count = n;
  return cloud;
}

}  // namespace bead
