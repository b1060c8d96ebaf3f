#include "libbead/sim/command_signal.h"

#include <cmath>
#include <numeric>

namespace bead::sim {

double StepsAt(const std::vector<double>& levels, const std::vector<double>& durations, double t) {
  const double period = std::accumulate(durations.begin(), durations.end(), 0.0);
  if (levels.empty() || !(period > 0)) return 0.0;
  double local = std::fmod(std::max(t, 0.0), period);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (local < durations[i]) return levels[i];
    local -= durations[i];
  }
  return levels.back();
}

double BaseLevel(const CommandConfig& c) {
  return c.kind == CommandConfig::Kind::kSteps && !c.levels_v.empty() ? c.levels_v.front() : c.base_v;
}

std::vector<double> CommandSeries(const CommandConfig& c, double dt, std::size_t n, std::mt19937_64& rng, double t0,
                                  bool warm) {
  std::vector<double> u(n, 0.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  unsigned lfsr = 0x1FF & static_cast<unsigned>(rng() | 1u);  // PRBS9: x^9 + x^5 + 1
  double bit = 1.0, filtered = 0.0, next_bit_time = c.start_s;
  const double alpha = std::exp(-dt / std::max(c.bit_time_s, dt));
  // Scales the first-order filtered white noise to unit variance.
  const double gain = std::sqrt((1 + alpha) / (1 - alpha));
  for (std::size_t i = 0; i < n; ++i) {
    const double t = t0 + static_cast<double>(i) * dt;
    filtered = alpha * filtered + (1 - alpha) * gauss(rng);
    if (c.stop_s >= 0 && t >= c.stop_s) continue;
    if (t < c.start_s) {
      if (warm) u[i] = BaseLevel(c);
      continue;
    }
    switch (c.kind) {
      case CommandConfig::Kind::kConstant:
        u[i] = c.base_v;
        break;
      case CommandConfig::Kind::kSteps:
        u[i] = StepsAt(c.levels_v, c.durations_s, t - c.start_s);
        break;
      case CommandConfig::Kind::kPrbs:
        if (t >= next_bit_time) {
          const unsigned fb = ((lfsr >> 8) ^ (lfsr >> 4)) & 1u;
          lfsr = ((lfsr << 1) | fb) & 0x1FF;
          bit = (lfsr & 1u) ? 1.0 : -1.0;
          next_bit_time += c.bit_time_s;
        }
        u[i] = c.base_v + c.amplitude_v * bit;
        break;
      case CommandConfig::Kind::kGaussian:
        u[i] = c.base_v + c.amplitude_v * gain * filtered;
        break;
    }
  }
  return u;
}

}  // namespace bead::sim
