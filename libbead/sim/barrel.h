// The extruder barrel's temperature, for the twin's recorded channels.
// The wall follows a first-order heat balance (lumped capacitance):
//   dT/dt = (T_heater - T) / tau_wall   while the heater is on,
//   dT/dt = (T_ambient - T) / tau_wall  while it is off,
// a thermocouple reads it through its own lag, and the controller acts on
// that reading: bang-bang between setpoint -+ band/2 (a 20 s cycle for the
// defaults), or a PID on the heater's duty. The melt follows the wall
// through its own lag, and the flow at a given screw speed changes with the
// melt's temperature (seed 003, section 3.4, "Flow Rate Output based on
// Screw Speed and Temperature", and its Table 8, temperature stepped at a
// constant screw speed; the same rig held its barrel by bang-bang control)
// by flow_per_c per degree from the setpoint. Units: degrees Celsius,
// seconds.
#pragma once

#include <cstdint>
#include <random>

namespace bead::sim {

struct BarrelConfig {
  bool record = false;  // log /log/barrel_temp_c (unit "C")
  enum class Control { kBangBang, kPid } control = Control::kBangBang;
  double setpoint_c = 200.0;
  double band_c = 8.0;        // bang-bang: on below setpoint - band/2, off above setpoint + band/2
  double heater_c = 260.0;    // the wall's temperature with the heater on for ever
  double ambient_c = 140.0;   // ... and off (the hot machine around it)
  double wall_tau_s = 60.0;   // about 1 C/s either way near 200 C: a 20 s cycle (16 s over the band, 4 s of sensor lag)
  double sensor_tau_s = 1.0;  // the thermocouple's lag
  double melt_tau_s = 2.0;    // the melt's lag behind the wall
  double noise_c = 0.05;      // the reading's white noise
  double kp = 0.5, ki = 0.02, kd = 0.0;  // PID: duty per degree, per degree second, per degree per second
  double flow_per_c = 0.0;               // relative flow change per degree of melt above the setpoint
  bool record_ambient = false;           // also log /log/ambient_temp_c, a slow random walk that acts on nothing
};

class Barrel {
 public:
  Barrel(const BarrelConfig& config, double dt_s);
  // One step: advances wall, reading and melt.
  void Step(std::mt19937_64& rng);
  double reading_c() const { return reading_; }
  double melt_c() const { return melt_; }
  double ambient_c() const { return ambient_walk_; }
  double flow_factor() const { return 1.0 + config_.flow_per_c * (melt_ - config_.setpoint_c); }

 private:
  double Duty();
  BarrelConfig config_;
  double dt_;
  double wall_, sensor_, reading_, melt_;
  bool heating_ = true;
  double integral_ = 0.0, last_error_ = 0.0;
  double ambient_walk_ = 22.0;
};

}  // namespace bead::sim
