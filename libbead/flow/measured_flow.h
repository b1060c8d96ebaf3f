// A run in memory measured and its flow computed in one call: every
// profile's geometry against the rig's reference areas (all cores,
// profile/measure_block.h), then Q = v A in extrusion time (flow.h). What
// the twin's users and tests do with a simulated run; an archive on disk
// goes through archive/ (streamed, flat memory) instead.
#pragma once

#include <vector>

#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/flow/flow.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/profile_processor.h"

namespace bead {

struct GeometryAndFlow {
  std::vector<BeadGeometry> geometry;
  FlowResult flow;
};

GeometryAndFlow MeasureFlow(const Rig& rig, const ProfileBlock& profiles, const AcquisitionLog& log,
                            const FlowOptions& flow_options = {}, const ProfileOptions& profile_options = {});

}  // namespace bead
