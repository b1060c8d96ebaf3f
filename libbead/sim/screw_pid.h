// The twin's screw-speed PID (SimConfig's extruder.pid): control/
// digital_pid.h's controller ticking every `ticks` simulator steps on the
// speed measured at the tick, its voltage held in between and clamped to
// [0, max_v].
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "libbead/control/digital_pid.h"
#include "libbead/sim/sim_config.h"

namespace bead::sim {

class ScrewPid {
 public:
  ScrewPid(const ScrewPidConfig& c, double dt)
      : ticks_(std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / (c.rate_hz * dt))))),
        pid_({c.kp, c.ki, c.kd, c.derivative_filter_s}, static_cast<double>(ticks_) * dt, 0.0, c.max_v) {}
  // In steady state at v0: no derivative kick on the first tick.
  void Start(double v0) { pid_.Start(v0, std::nullopt); }
  double Step(double setpoint, double measured, double held) {
    if (count_++ % ticks_ != 0) return held;
    return pid_.Update(setpoint - measured);
  }

 private:
  std::size_t ticks_, count_ = 0;
  control::DigitalPid pid_;
};

}  // namespace bead::sim
