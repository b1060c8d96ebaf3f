// Closing the loop on the data: the run's flow with the effects explain
// kept that act on the measurement (not on the process) undone.
//  - encoder_offset: the flow recomputed with the offset the run implies
//    (the rig file's plus the shift found), when the effect was kept or the
//    run's offset profile excludes the rig file's offset;
//  - once/twice per revolution of the wheel: the surface speed at the
//    nozzle divided by the term (an eccentric wheel's speed error);
//  - cooling_shrink: the area divided by the shrink's change with the time
//    to laser (only that change is in the data: its constant part is a
//    gain, taken by the base model, and stays);
//  - height_dependence: the area divided by the term (occlusion left over).
// Each corrected sample's sigma adds the kept terms' parameter covariance
// and the offset's interval to the measurement's own. The correction is
// for writing only when it lowers the held-out error (lowers_error).
// Effects of the process (the screw's pulsation, build-up, drift, a gain
// or lag that changes with level) are real flow and stay.
#pragma once

#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/flow/flow.h"
#include "libbead/core/run_data.h"
#include "libbead/model/transfer_function.h"
#include "libbead/profile/bead_geometry.h"

namespace bead::explain {

bool ActsOnMeasurement(const Effect& effect);

// The kept terms that act on the measurement, as factors at each sample of
// `d`: on the wheel's surface speed (its periodic terms) and on the area
// (shrink, height), each term less its mean over the run; and the relative
// variance of their product from the parameters' covariance (`covariance`
// flattened as ParameterCovariance::Matrix(); `first_slot`: each kept
// term's first parameter's slot in it), what the corrected flow's sigma
// adds for them.
struct MeasurementFactors {
  std::vector<double> speed, area, relative_variance;
};
MeasurementFactors FactorsOf(const SeriesData& d, const std::vector<Active>& kept,
                             const std::vector<std::size_t>& first_slot, const std::vector<double>& covariance);

struct CorrectedFlow {
  FlowResult flow;
  double offset_counts = 0.0;       // the offset the flow was computed with
  std::vector<std::string> undone;  // the effects undone
  // Held-out RMS of flow - the model (the base and the process's own
  // effects fitted to each flow on every other of 20 time blocks, the
  // error taken on the blocks between), mm^3/s, before and after.
  double rms_before = 0.0, rms_after = 0.0;
  bool lowers_error = false;  // write it only then
  std::string why_not;        // when not: why, in words
};

// `corrected_area` and `corrected_sigma`: the occlusion stage's columns
// that gave `report`'s flow (may be empty, as for ComputeFlow).
CorrectedFlow CorrectFlow(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                          const AcquisitionLog& log, const std::vector<double>& corrected_area,
                          const std::vector<double>& corrected_sigma, const ExplainReport& report,
                          const model::TransferFunction& model, double model_offset);

}  // namespace bead::explain
