// Extruder command voltage sampled on the simulator's fine time grid:
// constant, steps, PRBS (a maximum-length 9-bit shift register, as system
// identification uses, thesis 1.5.3.1), or a Gaussian random signal
// low-passed to a correlation time. 0 V outside [start_s, stop_s].
#pragma once

#include <random>
#include <vector>

#include "libbead/sim/sim_config.h"

namespace bead::sim {

// Sample i is at time t0_s + i dt_s. With `warm`, the command holds its
// base level (BaseLevel) before start_s instead of 0 V.
std::vector<double> CommandSeries(const CommandConfig& config, double dt_s, std::size_t samples, std::mt19937_64& rng,
                                  double t0_s = 0.0, bool warm = false);

// The level a command rests at: the first step level, else base_v.
double BaseLevel(const CommandConfig& config);

// Piecewise-constant levels repeated: value at time t (s) after their start.
double StepsAt(const std::vector<double>& levels, const std::vector<double>& durations, double t);

}  // namespace bead::sim
