#include "libbead/flow/measured_flow.h"

#include "libbead/profile/measure_block.h"

namespace bead {

GeometryAndFlow MeasureFlow(const Rig& rig, const ProfileBlock& profiles, const AcquisitionLog& log,
                            const FlowOptions& flow_options, const ProfileOptions& profile_options) {
  GeometryAndFlow out;
  out.geometry = MeasureProfiles(
      profiles.size(), [&](std::size_t i) { return profiles.view(i); }, rig.reference_left, rig.reference_right,
      profile_options);
  out.flow = ComputeFlow(rig, profiles, out.geometry, log, flow_options);
  return out;
}

}  // namespace bead
