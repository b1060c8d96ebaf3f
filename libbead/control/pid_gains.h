// A PID's gains, in the ideal (parallel) form
//   C(s) = kp + ki / s + kd s / (tf_s s + 1).
#pragma once

namespace bead::control {

struct Pid {
  double kp = 0, ki = 0, kd = 0;
  double tf_s = 0;  // derivative filter time constant (0: none)
};

}  // namespace bead::control
