// SimConfig: every parameter of the rig's digital twin, with defaults from
// the bead characterisation system thesis (large-scale AM extruder dynamics) where the thesis gives them. Read
// from YAML by ReadSimConfig (sim_config_yaml.cc); every key is optional.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/model/transfer_function.h"
#include "libbead/sim/barrel.h"

namespace bead::sim {

// Extruder command voltage over time.
struct CommandConfig {
  enum class Kind { kConstant, kSteps, kPrbs, kGaussian } kind = Kind::kSteps;
  double base_v = 3.0;                                               // constant level, PRBS/Gaussian mean
  std::vector<double> levels_v = {0.0, 3.0, 4.0, 2.5, 3.5, 0.0};     // steps: each level ...
  std::vector<double> durations_s = {1.0, 4.0, 4.0, 4.0, 4.0, 3.0};  // ... held this long (repeats)
  double amplitude_v = 0.8;                                          // PRBS +-amplitude; Gaussian standard deviation
  double bit_time_s = 0.5;                                           // PRBS bit length; Gaussian correlation time
  double start_s = 0.5;  // command is 0 V before this (extruder off; base level with warm_start)
  double stop_s = -1.0;  // command is 0 V after this (< 0: end of run)
};

// A PID on the screw speed (control/closed_loop.h's form, seed 004 eq. 16):
// with it, the extruder's `command` is the screw speed setpoint in RPM and
// the PID, ticking at rate_hz on the measured (noisy) speed, computes the
// voltage, clamped to [0, max_v] (its integral held while clamped).
struct ScrewPidConfig {
  bool on = false;
  double kp = 0, ki = 0, kd = 0, derivative_filter_s = 0;
  double rate_hz = 100.0, max_v = 10.0;
};

struct ExtruderConfig {
  CommandConfig command;
  ScrewPidConfig pid;
  model::TransferFunction voltage_to_rpm = model::ThesisVoltageToRpm();  // thesis eq. 21
  model::TransferFunction rpm_to_flow = model::ThesisRpmToFlow(0.15);    // thesis eq. 22; delay ours
  double rpm_noise = 0.3;                                                // RPM, white, on the screw speed
  double flow_noise_frac = 0.01;                                         // relative, low-pass (0.2 s) on the flow
};

struct WheelConfig {
  enum class Mode { kConstant, kCommanded, kFeedForward } mode = Mode::kConstant;
  double surface_speed_mm_s = 200.0;         // constant mode (15 RPM of the 254.762 mm wheel is 200 mm/s)
  double target_area_mm2 = 14.0;             // feed-forward: the area to hold ...
  double controller_rate_hz = 100.0;         // ... by a controller ticking at this rate (model/feed_forward.h)
  double gain_rpm_per_v = 2.517;             // thesis 3.3.3: wheel voltage -> RPM, first order ...
  double tau_s = 0.0377;                     // ... with this time constant ...
  double delay_s = 0.009;                    // ... and delay
  std::vector<double> cmd_levels_v = {6.0};  // commanded mode: wheel voltage steps
  std::vector<double> cmd_durations_s = {1e9};
};

struct EncoderConfig {
  int64_t start_count = 123456;   // raw counter at t = 0
  double missed_read_prob = 0.0;  // chance a read repeats the previous value
};

struct BeadConfig {
  enum class Shape { kRoundedRectangle, kSuperellipse, kParabola } shape = Shape::kRoundedRectangle;
  double aspect = 1.6;                  // max width / height
  double bottom_radius_frac = 0.25;     // rounded rectangle: bottom corner radius / height (undercut)
  double top_radius_frac = 0.35;        // rounded rectangle: top corner radius / height
  double exponent = 2.5;                // superellipse exponent (above its widest point)
  double bottom_exponent = 0.0;         // below its widest point (0: the same): not symmetric
  double center_lift_frac = 0.3;        // superellipse: centre height / half-height (undercut)
  double center_wander_mm = 0.3;        // bead centre wanders by up to this ...
  double center_wander_period_s = 7.0;  // ... with this period
  int outline_vertices = 96;
};

struct SensorConfig {
  double rate_hz = 200.0;  // profiles per second (scanCONTROL 2610 at 200 Hz, thesis 2.2.1)
  int points = 640;
  double x_min_mm = -25.0, x_max_mm = 25.0;  // where the rays meet the nominal surface
  bool fan = true;                           // rays from laser_origin (else parallel, straight down)
  double z_sigma_mm = 0.005;
  double z_quantum_mm = 0.001;
  double dropout_prob = 0.003;
  double spike_prob = 0.001;
  double spike_mm = 2.0;
  double dropped_profile_prob = 0.002;
  double roll_deg = 0.5;
  double runout_mm = 0.05;  // once-per-revolution surface height change at the laser
};

struct PinConfig {
  int scans = 6;
  double placement_sigma_mm = 0.35;  // human placement error along the travel
  double diameter_mm = 3.0;
  double height_mm = 6.0;
  double scan_speed_mm_s = 10.0;
  double scan_half_length_mm = 8.0;  // each scan covers the laser +- this
};

// Effects a real rig shows; off by default.
struct EffectsConfig {
  double eccentricity_mm = 0.0;          // wheel radius varies as R + e cos(angle)
  double shrink_frac = 0.0;              // area shrinks by this fraction ...
  double shrink_tau_s = 1.0;             // ... approached with this time constant after laying
  double rig_offset_error_counts = 0.0;  // the written rig file's offset is off by this
  double sensor_latency_s = 0.0;         // profile time stamps late by this
};

struct SimConfig {
  uint64_t seed = 1;
  double duration_s = 20.0;
  double dt_s = 0.0005;  // inner integration step
  // The run is a cut from a longer session: it begins in steady state at
  // the command's base level (before start_s the command holds that level,
  // not 0 V), the wheel already turning, bead already under the laser.
  bool warm_start = false;
  double log_rate_hz = 500.0;
  Rig rig;  // what the rig really is (offset: the true offset)
  ExtruderConfig extruder;
  WheelConfig wheel;
  EncoderConfig encoder;
  BeadConfig bead;
  SensorConfig sensor;
  PinConfig pins;
  EffectsConfig effects;
  BarrelConfig barrel;  // the barrel's temperature: a recorded channel, and an effect on the flow

  SimConfig();
};

// Reads a config; keys not given keep their defaults. Errors name the file,
// the line and the key.
SimConfig ReadSimConfig(const std::string& path);
SimConfig ParseSimConfig(const std::string& text, const std::string& name);

}  // namespace bead::sim
