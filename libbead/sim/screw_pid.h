// The twin's screw-speed PID (SimConfig's extruder.pid): a digital PID
// ticking every `ticks` simulator steps on the speed measured at the
// tick, its voltage held in between and clamped to [0, max_v], the
// integral frozen while the output is clamped (control/closed_loop.h's
// controller form).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "libbead/sim/sim_config.h"

namespace bead::sim {

class ScrewPid {
 public:
  ScrewPid(const ScrewPidConfig& c, double dt)
      : c_(c),
        ticks_(std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / (c.rate_hz * dt))))),
        dt_(static_cast<double>(ticks_) * dt) {}
  void Start(double v0) { integral_ = c_.ki != 0 ? v0 / c_.ki : 0.0, first_ = true; }
  double Step(double setpoint, double measured, double held) {
    if (count_++ % ticks_ != 0) return held;
    const double e = setpoint - measured;
    if (first_) prev_e_ = e, first_ = false;
    deriv_ = c_.derivative_filter_s > 0
                 ? (c_.derivative_filter_s * deriv_ + c_.kd * (e - prev_e_)) / (c_.derivative_filter_s + dt_)
                 : c_.kd * (e - prev_e_) / dt_;
    prev_e_ = e;
    const double raw = c_.kp * e + c_.ki * (integral_ + e * dt_) + deriv_;
    const double out = std::clamp(raw, 0.0, c_.max_v);
    if (out == raw) integral_ += e * dt_;
    return out;
  }

 private:
  ScrewPidConfig c_;
  std::size_t ticks_, count_ = 0;
  double dt_, integral_ = 0, prev_e_ = 0, deriv_ = 0;
  bool first_ = true;
};

}  // namespace bead::sim
