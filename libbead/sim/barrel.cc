#include "libbead/sim/barrel.h"

#include <algorithm>
#include <cmath>

namespace bead::sim {

Barrel::Barrel(const BarrelConfig& c, double dt_s) : config_(c), dt_(dt_s) {
  wall_ = sensor_ = reading_ = melt_ = c.setpoint_c;
}

double Barrel::Duty() {
  const double error = config_.setpoint_c - reading_;
  if (config_.control == BarrelConfig::Control::kBangBang) {
    if (reading_ < config_.setpoint_c - 0.5 * config_.band_c) heating_ = true;
    if (reading_ > config_.setpoint_c + 0.5 * config_.band_c) heating_ = false;
    return heating_ ? 1.0 : 0.0;
  }
  // The steady duty that holds the setpoint, and the PID about it.
  const double hold = (config_.setpoint_c - config_.ambient_c) / (config_.heater_c - config_.ambient_c);
  const double derivative = (error - last_error_) / dt_;
  last_error_ = error;
  const double raw = hold + config_.kp * error + config_.ki * integral_ + config_.kd * derivative;
  if (raw > 0.0 && raw < 1.0) integral_ += error * dt_;  // no wind-up at the limits
  return std::clamp(raw, 0.0, 1.0);
}

void Barrel::Step(std::mt19937_64& rng) {
  const double duty = Duty();
  const double target = config_.ambient_c + duty * (config_.heater_c - config_.ambient_c);
  const double a_wall = std::exp(-dt_ / config_.wall_tau_s);
  wall_ = target + (wall_ - target) * a_wall;
  const double a_sensor = std::exp(-dt_ / config_.sensor_tau_s);
  sensor_ = wall_ + (sensor_ - wall_) * a_sensor;
  const double a_melt = std::exp(-dt_ / config_.melt_tau_s);
  melt_ = wall_ + (melt_ - wall_) * a_melt;
  std::normal_distribution<double> gauss(0.0, 1.0);
  reading_ = sensor_ + config_.noise_c * gauss(rng);
  // The room: a random walk of 0.05 C per sqrt(s), held near 22 C.
  ambient_walk_ += 0.05 * std::sqrt(dt_) * gauss(rng) - (ambient_walk_ - 22.0) * dt_ / 600.0;
}

}  // namespace bead::sim
