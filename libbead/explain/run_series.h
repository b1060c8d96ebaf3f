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

// With `bin` > 1 each sample stands for `bin` consecutive profiles: their
// mean count searched for its extrusion time (as the shift hook searches),
// their mean area times the surface speed there, their mean height, time
// to the laser and wheel angle; `profile` then names each bin's middle
// profile and an incomplete last bin is left out. A long run explained at
// a rate that still resolves its rotating parts (ExplainBin) costs a bin's
// fraction of the per-profile series.
RunSeries MakeRunSeries(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                        const AcquisitionLog& log, const FlowResult& flow, const model::TransferFunction& rpm_to_flow,
                        double model_offset = 0.0, const FlowOptions& flow_options = {}, std::size_t bin = 1);

// The profiles per sample for explaining `samples` flow samples over
// `duration_s`: enough that at most 16384 samples remain, but never a
// sample rate under 25 Hz (the twice-per-revolution term of a screw at
// 300 RPM, 10 Hz, stays below its Nyquist rate of 12.5 Hz). 1 for a run
// that is short or slow already.
std::size_t ExplainBin(std::size_t samples, double duration_s);

// `v` averaged over consecutive bins of `bin` (an incomplete last one left
// out), as MakeRunSeries bins a run.
std::vector<double> AverageInBins(const std::vector<double>& v, std::size_t bin);

// A flow's valid samples (time, screw speed, flow) averaged in bins of
// `bin`: what a base model is identified on.
struct BinnedFlow {
  std::vector<double> t, u, y;
};
BinnedFlow BinValidFlow(const FlowResult& flow, std::size_t bin);

}  // namespace bead::explain
