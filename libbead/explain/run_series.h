// SeriesData for a run of the rig: the measured flow Q = v A of each
// profile in extrusion time (flow.h) against a model of the flow from the
// screw speed (y = offset + G(s) rpm), simulated on the log's times from
// steady state at the log's first screw speed (a run cut from a longer
// session is in steady state or near it; the refitted operating point and
// gain take up the rest). What the run lets us
// reconstruct rides along: the wheel's angle where the bead was laid and
// the screw's angle (integral of its speed) - the rotating parts -, the
// time from laying to measuring, the bead's height. Moving the data in
// wheel position re-finds every extrusion time with the offset changed, so
// the encoder offset can be estimated from the run itself.
#pragma once

#include <vector>

#include "libbead/core/rig.h"
#include "libbead/explain/series_data.h"
#include "libbead/flow/flow.h"
#include "libbead/core/run_data.h"
#include "libbead/model/transfer_function.h"
#include "libbead/profile/bead_geometry.h"

namespace bead::explain {

struct RunSeries {
  SeriesData data;
  std::vector<std::size_t> profile;  // the profile of each sample
  // The profiles' time stamps against the log: the median of (stamp - the
  // time the log's encoder read the profile's own count), with its 95 %
  // interval; a sensor latency shows here (the flow itself uses the
  // profile's latched count, so it does not see one).
  double timestamp_offset_s = 0.0, timestamp_offset_ci95_s = 0.0;
};

RunSeries MakeRunSeries(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                        const AcquisitionLog& log, const FlowResult& flow, const model::TransferFunction& rpm_to_flow,
                        double model_offset = 0.0, const FlowOptions& flow_options = {});

}  // namespace bead::explain
