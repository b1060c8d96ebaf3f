// Feed-forward of the wheel (thesis chapter 4, 4.2): the wheel speed that
// lays a target bead area for the flow the models predict from the
// extruder command, so no measurement is needed in the loop.
//
// At the controller's rate dt:
//  1. the extruder command runs through the voltage -> RPM and RPM -> flow
//     models (exact ZOH at dt), their delays shortened by the wheel's own
//     delay so the wheel gets its command that much ahead of the flow;
//  2. the reference surface speed v = Q / A_target (never below a crawl
//     that keeps the wheel turning), in wheel RPM, in volts through the
//     wheel's gain (thesis 3.3.3: first order, gain K, time constant tau);
//  3. the thesis's control block (4.2.1): a zero on the modelled wheel pole
//     a = exp(-dt / tau) and a pole at 0.01, unit DC gain,
//       C(z) = (1 - p) / (1 - a) * (z - a) / (z - p),   p = 0.01,
//     so the wheel answers in about one controller tick instead of tau;
//  4. the command clamped to [0, max_voltage].
// Models identified on the rig (bead identify) or the thesis defaults.
#pragma once

#include <deque>

#include "libbead/model/transfer_function.h"

namespace bead::model {

struct WheelModel {  // thesis 3.3.3: wheel voltage -> RPM
  double gain_rpm_per_v = 2.517;
  double tau_s = 0.0377;
  double delay_s = 0.009;
  double radius_mm = 127.381;  // surface radius (254.762 mm wheel)
};

struct FeedForwardOptions {
  double target_area_mm2 = 14.0;
  double rate_hz = 100.0;  // controller rate
  double pole = 0.01;      // thesis 4.2.1
  double min_speed_mm_s = 20.0;
  double max_voltage_v = 10.0;
};

class FeedForward {
 public:
  FeedForward(const TransferFunction& voltage_to_rpm, const TransferFunction& rpm_to_flow, const WheelModel& wheel,
              const FeedForwardOptions& options);

  // One controller tick: the extruder command now -> the wheel command now (V).
  double Step(double extruder_command_v);
  // The models in steady state at this extruder command, as if it had
  // always been given (a plan that starts mid-process); else they start
  // from rest.
  void StartAt(double extruder_command_v);
  // The flow the models predict one wheel delay ahead, mm^3/s (last tick).
  double predicted_flow_mm3_s() const { return predicted_; }
  double dt_s() const { return dt_; }

 private:
  double dt_;
  WheelModel wheel_;
  FeedForwardOptions options_;
  DiscreteSystem to_rpm_, to_flow_;
  std::deque<double> command_delay_, rpm_delay_;  // ticks of delay in each model
  double a_, gain_, to_rpm_dc_ = 0.0;
  double last_reference_v_ = 0.0, last_output_v_ = 0.0, predicted_ = 0.0;
  bool first_ = true;
};

}  // namespace bead::model
