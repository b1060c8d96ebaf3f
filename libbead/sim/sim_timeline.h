// The twin's dynamics on its fine time grid (RunDynamics: the extruder,
// its screw-speed PID, the barrel, the wheel and its controller), which
// the sensor and the log are then sampled from (rig_simulator.cc).
// Internal to sim/; not installed.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "libbead/sim/sim_config.h"

namespace bead::sim {

// The wheel, extruder and their histories on the fine time grid.
struct Timeline {
  double dt = 0;
  double t0 = 0;  // time of the first sample (before 0 for a warm start)
  std::vector<double> command_v, wheel_cmd_v, rpm, flow, angle, speed, area;
  std::vector<double> barrel_c, ambient_c;  // the recorded channels (empty when not simulated)

  double Index(double t) const { return (t - t0) / dt; }
  double Time(double index) const { return t0 + index * dt; }
  // First fractional index where the (non-decreasing) angle reaches `a`; -1 when before the start.
  double IndexOfAngle(double a) const {
    if (a < angle.front()) return -1.0;
    const auto it = std::lower_bound(angle.begin(), angle.end(), a);
    if (it == angle.end()) return static_cast<double>(angle.size() - 1);
    const auto i = static_cast<std::size_t>(it - angle.begin());
    if (i == 0) return 0.0;
    const double a0 = angle[i - 1], a1 = angle[i];
    return static_cast<double>(i - 1) + (a1 > a0 ? (a - a0) / (a1 - a0) : 1.0);
  }
};

// The timeline of config `c`, its noise drawn from `rng` (the barrel's
// from a stream of its own, so a run without it keeps its noise).
Timeline RunDynamics(const SimConfig& c, std::mt19937_64& rng);

}  // namespace bead::sim
