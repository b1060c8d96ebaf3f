// The thesis' feed-forward (chapter 4, model/feed_forward.h) as a plan the
// rig can play: from the planned extruder command, the wheel command that
// holds a target bead area, at the controller's rate, with what the models
// predict beside it (the flow, the wheel's surface speed, the area) and
// the area a constant wheel would lay instead.
#pragma once

#include <vector>

#include "libbead/model/feed_forward.h"
#include "libbead/model/transfer_function.h"

namespace bead::control {

struct WheelPlan {
  std::vector<double> t_s, extruder_cmd_v, wheel_cmd_v;  // at the controller's rate
  std::vector<double> flow_mm3_s, speed_mm_s, area_mm2;  // the models' prediction
  // The predicted area's RMS deviation from the target, relative, under the
  // plan and under a constant wheel at the speed that lays the target area
  // at the plan's mean flow (the thesis' comparison, its Table 4).
  double rms_rel_planned = 0, rms_rel_constant = 0;
};

// `t`, `extruder_v`: the planned command (held between its samples, t
// increasing). The models start in steady state at its first value.
// Throws bead::Error on a plan of fewer than 2 samples.
WheelPlan PlanWheel(const std::vector<double>& t, const std::vector<double>& extruder_v,
                    const model::TransferFunction& voltage_to_rpm, const model::TransferFunction& rpm_to_flow,
                    const model::WheelModel& wheel, const model::FeedForwardOptions& options);

}  // namespace bead::control
