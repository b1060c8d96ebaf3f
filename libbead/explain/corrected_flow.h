// Closing the loop on the data: the run's flow with the effects explain
// kept that act on the measurement (not on the process) undone.
//  - encoder_offset: the flow recomputed with the offset the run implies
//    (the rig file's plus the shift found), when the effect was kept or the
//    run's offset profile excludes the rig file's offset;
//  - once/twice per revolution of the wheel: the surface speed at the
//    nozzle divided by the term (an eccentric wheel's speed error);
//  - cooling_shrink: the area divided by (1 - shrink at its time to laser),
//    the material's size when laid;
//  - height_dependence: the area divided by the term (occlusion left over).
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

struct CorrectedFlow {
  FlowResult flow;
  double offset_counts = 0.0;       // the offset the flow was computed with
  std::vector<std::string> undone;  // the effects undone
  // RMS of flow - the model (the base and the process's own effects,
  // refitted to each flow), mm^3/s, before and after.
  double rms_before = 0.0, rms_after = 0.0;
};

// `corrected_area` and `corrected_sigma`: the occlusion stage's columns
// that gave `report`'s flow (may be empty, as for ComputeFlow).
CorrectedFlow CorrectFlow(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                          const AcquisitionLog& log, const std::vector<double>& corrected_area,
                          const std::vector<double>& corrected_sigma, const ExplainReport& report,
                          const model::TransferFunction& model, double model_offset);

}  // namespace bead::explain
