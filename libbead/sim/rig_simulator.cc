#include "libbead/sim/rig_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

#include "libbead/model/feed_forward.h"
#include "libbead/sim/screw_pid.h"
#include "libbead/sim/bead_shapes.h"
#include "libbead/sim/command_signal.h"
#include "libbead/sim/sensor_model.h"

namespace bead::sim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The raw counter for a continuous count, as the rig file's encoder reports it.
int64_t RawCounter(const Rig& rig, int64_t start, double counts) {
  const int64_t steps = static_cast<int64_t>(std::floor(counts));
  int64_t raw = start + rig.encoder.direction * steps;
  if (rig.encoder.bits > 0 && rig.encoder.bits < 64) {
    const int64_t modulus = int64_t{1} << rig.encoder.bits;
    raw %= modulus;
    if (raw < 0) raw += modulus;
  }
  return raw;
}

// Linear interpolation of y at fractional fine-grid index.
double At(const std::vector<double>& y, double index) {
  const double clamped = std::clamp(index, 0.0, static_cast<double>(y.size() - 1));
  const auto i = static_cast<std::size_t>(clamped);
  if (i + 1 >= y.size()) return y.back();
  const double f = clamped - static_cast<double>(i);
  return y[i] + f * (y[i + 1] - y[i]);
}

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

Timeline RunDynamics(const SimConfig& c, std::mt19937_64& rng) {
  Timeline tl;
  tl.dt = c.dt_s;
  const double radius = c.rig.wheel_diameter_mm / 2;
  if (c.warm_start) {
    // Long enough for the material under the laser at t = 0 to have been
    // laid in steady state: the wheel's travel from nozzle to laser at its
    // starting speed, and a second more.
    const double omega0 =
        c.wheel.mode == WheelConfig::Mode::kConstant
            ? c.wheel.surface_speed_mm_s / radius
            : std::max(0.05, c.wheel.gain_rpm_per_v * StepsAt(c.wheel.cmd_levels_v, c.wheel.cmd_durations_s, 0.0) *
                                 kTwoPi / 60.0);
    const double travel = kTwoPi * c.rig.offset_counts / c.rig.encoder.counts_per_rev / omega0;
    tl.t0 = -c.dt_s * std::ceil((travel + 1.0 + c.wheel.tau_s * 10) / c.dt_s);
  }
  const std::size_t n = static_cast<std::size_t>(std::ceil((c.duration_s - tl.t0) / c.dt_s)) + 1;
  tl.command_v = CommandSeries(c.extruder.command, c.dt_s, n, rng, tl.t0, c.warm_start);
  // With a screw-speed PID the command is its setpoint (RPM); the voltage
  // is computed in the loop below.
  ScrewPid pid(c.extruder.pid, c.dt_s);
  std::vector<double> setpoint_rpm;
  if (c.extruder.pid.on) {
    setpoint_rpm = tl.command_v;
    const double v0 = c.warm_start ? setpoint_rpm.front() / c.extruder.voltage_to_rpm.DcGain() : 0.0;
    std::fill(tl.command_v.begin(), tl.command_v.end(), v0);
    pid.Start(v0);
  }
  tl.wheel_cmd_v.assign(n, 0.0);
  tl.rpm.assign(n, 0.0);
  tl.flow.assign(n, 0.0);
  tl.angle.assign(n, 0.0);
  tl.speed.assign(n, 0.0);
  tl.area.assign(n, 0.0);

  model::DiscreteSystem to_rpm(c.extruder.voltage_to_rpm, c.dt_s), to_flow(c.extruder.rpm_to_flow, c.dt_s);
  // The feed-forward wheel controller (thesis 4.2), ticking at its own rate
  // on noise-free models; its command is held between ticks.
  std::optional<model::FeedForward> feed_forward;
  std::size_t controller_ticks = 1;
  if (c.wheel.mode == WheelConfig::Mode::kFeedForward) {
    model::WheelModel wheel{c.wheel.gain_rpm_per_v, c.wheel.tau_s, c.wheel.delay_s, c.rig.wheel_diameter_mm / 2};
    model::FeedForwardOptions fo;
    fo.target_area_mm2 = c.wheel.target_area_mm2;
    fo.rate_hz = c.wheel.controller_rate_hz;
    feed_forward.emplace(c.extruder.voltage_to_rpm, c.extruder.rpm_to_flow, wheel, fo);
    controller_ticks = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / (fo.rate_hz * c.dt_s))));
  }
  const auto lag = [&](double delay) { return static_cast<std::size_t>(std::llround(delay / c.dt_s)); };
  const std::size_t rpm_lag = lag(c.extruder.voltage_to_rpm.delay_s), flow_lag = lag(c.extruder.rpm_to_flow.delay_s);
  const std::size_t wheel_lag = lag(c.wheel.delay_s);
  double wheel_rpm =
      c.wheel.mode == WheelConfig::Mode::kConstant ? c.wheel.surface_speed_mm_s / radius * 60.0 / kTwoPi : 0.0;
  double rpm_before = 0.0, wheel_cmd_before = 0.0;  // inputs before the first sample (delays)
  if (c.warm_start) {
    // Extruder and wheel in steady state at their first commands.
    const double v0 = tl.command_v.front();
    rpm_before = c.extruder.voltage_to_rpm.DcGain() * v0;
    to_rpm.Reset(v0);
    to_flow.Reset(rpm_before);
    if (c.wheel.mode == WheelConfig::Mode::kCommanded) {
      wheel_cmd_before = StepsAt(c.wheel.cmd_levels_v, c.wheel.cmd_durations_s, 0.0);
      wheel_rpm = c.wheel.gain_rpm_per_v * wheel_cmd_before;
    }
  }
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double noise_alpha = std::exp(-c.dt_s / 0.2);
  const double noise_gain = std::sqrt((1 + noise_alpha) / (1 - noise_alpha));
  double flow_noise = 0.0;
  // The barrel on a stream of its own: a run without it keeps its noise.
  const bool barrel_on = c.barrel.record || c.barrel.record_ambient || c.barrel.flow_per_c != 0.0;
  std::optional<Barrel> barrel;
  std::mt19937_64 barrel_rng(c.seed ^ 0xba77e1ULL);
  if (barrel_on) {
    barrel.emplace(c.barrel, c.dt_s);
    tl.barrel_c.assign(n, 0.0);
    tl.ambient_c.assign(n, 0.0);
  }

  for (std::size_t i = 0; i < n; ++i) {
    const double t = tl.Time(static_cast<double>(i));
    if (c.extruder.pid.on)
      tl.command_v[i] = pid.Step(setpoint_rpm[i], i > 0 ? tl.rpm[i - 1] : setpoint_rpm[i],
                                 i > 0 ? tl.command_v[i - 1] : tl.command_v[0]);
    const double u_rpm = i >= rpm_lag ? tl.command_v[i - rpm_lag] : (c.warm_start ? tl.command_v.front() : 0.0);
    tl.rpm[i] = std::max(0.0, to_rpm.Step(u_rpm) + c.extruder.rpm_noise * gauss(rng));
    const double u_flow = i >= flow_lag ? tl.rpm[i - flow_lag] : rpm_before;
    flow_noise = noise_alpha * flow_noise + (1 - noise_alpha) * gauss(rng);
    tl.flow[i] = std::max(0.0, to_flow.Step(u_flow) * (1.0 + c.extruder.flow_noise_frac * noise_gain * flow_noise));
    if (barrel) {
      barrel->Step(barrel_rng);
      tl.flow[i] *= barrel->flow_factor();
      tl.barrel_c[i] = barrel->reading_c();
      tl.ambient_c[i] = barrel->ambient_c();
    }

    // The wheel: its command, then its first-order response (thesis 3.3.3).
    switch (c.wheel.mode) {
      case WheelConfig::Mode::kConstant:
        break;
      case WheelConfig::Mode::kCommanded:
        tl.wheel_cmd_v[i] = StepsAt(c.wheel.cmd_levels_v, c.wheel.cmd_durations_s, t);
        break;
      case WheelConfig::Mode::kFeedForward:
        tl.wheel_cmd_v[i] = i % controller_ticks == 0 ? feed_forward->Step(tl.command_v[i]) : tl.wheel_cmd_v[i - 1];
        break;
    }
    if (c.wheel.mode != WheelConfig::Mode::kConstant) {
      const double v_in = i >= wheel_lag ? tl.wheel_cmd_v[i - wheel_lag] : wheel_cmd_before;
      const double a = std::exp(-c.dt_s / c.wheel.tau_s);
      wheel_rpm = a * wheel_rpm + (1 - a) * c.wheel.gain_rpm_per_v * v_in;
    }
    const double omega = std::max(0.0, wheel_rpm) * kTwoPi / 60.0;
    if (i > 0) tl.angle[i] = tl.angle[i - 1] + omega * c.dt_s;
    // Eccentricity: the radius under the nozzle varies with the angle.
    tl.speed[i] = omega * (radius + c.effects.eccentricity_mm * std::cos(tl.angle[i]));
    tl.area[i] = tl.speed[i] > 1e-9 ? tl.flow[i] / tl.speed[i] : 0.0;
  }
  return tl;
}

std::vector<float> TargetGrid(const SensorConfig& s) {
  std::vector<float> x(static_cast<std::size_t>(s.points));
  for (int j = 0; j < s.points; ++j)
    x[static_cast<std::size_t>(j)] = static_cast<float>(s.x_min_mm + (s.x_max_mm - s.x_min_mm) * j / (s.points - 1));
  return x;
}

// Renders one profile of `outline` into row `row` of `block` with noise.
struct ProfileRenderer {
  const SimConfig& c;
  std::vector<float> target;
  std::optional<Fan> fan;
  SensorNoise noise;
  double dropped_prob;

  explicit ProfileRenderer(const SimConfig& config) : c(config), target(TargetGrid(config.sensor)) {
    if (c.sensor.fan && c.rig.laser_origin) fan = Fan{c.rig.laser_origin->x_mm, c.rig.laser_origin->z_mm};
    noise = {c.sensor.z_sigma_mm, c.sensor.z_quantum_mm, c.sensor.dropout_prob, c.sensor.spike_prob, c.sensor.spike_mm};
    dropped_prob = c.sensor.dropped_profile_prob;
  }

  ProfileBlock NewBlock() const {
    ProfileBlock b;
    b.points = target.size();
    b.shared_x = !fan.has_value();
    if (b.shared_x) b.x_mm = target;
    return b;
  }

  // Appends a profile; returns true when the sensor dropped it whole.
  bool Append(ProfileBlock& b, const Outline& outline, const SensorPose& pose, std::mt19937_64& rng) const {
    const std::size_t p = target.size();
    std::vector<float> x(p), z(p);
    if (fan)
      RenderProfileFan(outline, pose, *fan, target, x, z);
    else
      RenderProfile(outline, pose, target, z);
    AddSensorNoise(z, noise, rng);
    const bool dropped = std::uniform_real_distribution<double>(0, 1)(rng) < dropped_prob;
    if (dropped) std::fill(z.begin(), z.end(), std::numeric_limits<float>::quiet_NaN());
    if (fan) {
      for (std::size_t j = 0; j < p; ++j)
        if (std::isnan(z[j])) x[j] = std::numeric_limits<float>::quiet_NaN();
      b.x_mm.insert(b.x_mm.end(), x.begin(), x.end());
    }
    b.z_mm.insert(b.z_mm.end(), z.begin(), z.end());
    return dropped;
  }
};

void SimulateProfiles(const SimConfig& c, const Timeline& tl, std::mt19937_64& rng, SimulatedRun& out) {
  const ProfileRenderer renderer(c);
  const Outline unit = UnitBeadOutline(c.bead);
  const double unit_area = OutlineArea(unit);
  const double offset_angle = kTwoPi * c.rig.offset_counts / c.rig.encoder.counts_per_rev;
  const double roll = c.sensor.roll_deg * std::numbers::pi / 180.0;
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  ProfileBlock& block = out.run.profiles;
  block = renderer.NewBlock();
  ProfileTruth& truth = out.truth.profiles;
  int64_t last_raw = c.encoder.start_count;
  const double wander_phase = kTwoPi * uni(rng);
  for (std::size_t k = 0;; ++k) {
    const double t = static_cast<double>(k) / c.sensor.rate_hz;
    if (t > c.duration_s) break;
    const double angle = At(tl.angle, tl.Index(t));
    // The material under the laser was laid when the wheel stood offset_angle earlier.
    const double ie = tl.IndexOfAngle(angle - offset_angle);
    double area = 0.0, t_e = kNaN, center = 0.0;
    if (ie >= 0.0) {
      t_e = tl.Time(ie);
      area = At(tl.area, ie);
      if (c.effects.shrink_frac > 0)  // cooling between nozzle and laser
        area *= 1.0 - c.effects.shrink_frac * (1.0 - std::exp(-(t - t_e) / c.effects.shrink_tau_s));
      center = c.bead.center_wander_mm * std::sin(kTwoPi * t_e / c.bead.center_wander_period_s + wander_phase);
    }
    const bool has_bead = area > 0.05;
    const Outline outline = has_bead ? ScaledOutline(unit, unit_area, area, center) : Outline{};
    SensorPose pose;
    pose.roll_rad = roll;
    // Runout: once per revolution; eccentricity moves the surface at the
    // laser too: the wheel point under it stood under the nozzle at
    // angle - offset_angle, where its radius was R + e cos(that angle)
    // (the sign was + before: the height's phase did not match the
    // speed's; nothing read the phase until `bead calibrate wheel`).
    pose.z_offset_mm =
        c.sensor.runout_mm * std::cos(angle) + c.effects.eccentricity_mm * std::cos(angle - offset_angle);
    const bool dropped = renderer.Append(block, outline, pose, rng);

    int64_t raw = RawCounter(c.rig, c.encoder.start_count, angle / kTwoPi * c.rig.encoder.counts_per_rev);
    if (k > 0 && uni(rng) < c.encoder.missed_read_prob) raw = last_raw;
    last_raw = raw;
    block.t_s.push_back(t + c.effects.sensor_latency_s);
    block.encoder.push_back(raw);

    const BeadDims dims = OutlineDims(outline);
    truth.t_s.push_back(t);
    truth.t_extruded_s.push_back(t_e);
    truth.area_true_mm2.push_back(has_bead ? OutlineArea(outline) : 0.0);
    truth.area_visible_mm2.push_back(has_bead ? VisibleArea(outline, pose, renderer.fan) : 0.0);
    truth.max_width_mm.push_back(dims.max_width_mm);
    truth.contact_width_mm.push_back(dims.contact_width_mm);
    truth.height_mm.push_back(dims.height_mm);
    truth.center_x_mm.push_back(has_bead ? center : kNaN);
    truth.dropped.push_back(dropped ? 1 : 0);
  }
}

void SimulateLog(const SimConfig& c, const Timeline& tl, std::mt19937_64& rng, SimulatedRun& out) {
  AcquisitionLog log;
  FlowTruth& flow = out.truth.flow;
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int64_t last = c.encoder.start_count;
  for (std::size_t j = 0;; ++j) {
    const double t = static_cast<double>(j) / c.log_rate_hz;
    if (t > c.duration_s) break;
    const double i = tl.Index(t);
    int64_t raw = RawCounter(c.rig, c.encoder.start_count, At(tl.angle, i) / kTwoPi * c.rig.encoder.counts_per_rev);
    if (j > 0 && uni(rng) < c.encoder.missed_read_prob) raw = last;
    last = raw;
    log.t_s.push_back(t);
    log.encoder.push_back(raw);
    log.screw_rpm.push_back(At(tl.rpm, i));
    log.extruder_cmd_v.push_back(At(tl.command_v, i));
    log.wheel_cmd_v.push_back(At(tl.wheel_cmd_v, i));
    flow.t_s.push_back(t);
    flow.flow_mm3_s.push_back(At(tl.flow, i));
    flow.area_mm2.push_back(At(tl.area, i));
    flow.surface_speed_mm_s.push_back(At(tl.speed, i));
    flow.screw_rpm.push_back(At(tl.rpm, i));
  }
  // Recorded channels, sampled like the rest of the log.
  auto channel = [&](const char* name, const char* unit, const std::vector<double>& series) {
    LogChannel ch{name, unit, {}};
    for (double t : log.t_s) ch.values.push_back(At(series, tl.Index(t)));
    log.channels.push_back(std::move(ch));
  };
  if (c.barrel.record) channel("barrel_temp_c", "C", tl.barrel_c);
  if (c.barrel.record_ambient) channel("ambient_temp_c", "C", tl.ambient_c);
  out.run.log = std::move(log);
  double volume = 0.0;  // laid during the record, t >= 0
  for (std::size_t i = 1; i < tl.flow.size(); ++i)
    if (tl.Time(static_cast<double>(i - 1)) >= -1e-12) volume += 0.5 * (tl.flow[i] + tl.flow[i - 1]) * c.dt_s;
  out.truth.total_volume_mm3 = volume;
}

// Pin scans: a pin placed under the nozzle (with human error along the
// travel), the counter read, then the wheel turned slowly past the laser.
void SimulatePins(const SimConfig& c, std::mt19937_64& rng, SimulatedRun& out) {
  const ProfileRenderer renderer(c);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double mm_per_count = c.rig.MmPerCount();
  const double offset_mm = c.rig.offset_counts * mm_per_count;
  const double r = c.pins.diameter_mm / 2;
  const double roll = c.sensor.roll_deg * std::numbers::pi / 180.0;
  for (int k = 0; k < c.pins.scans; ++k) {
    PinScan scan;
    const double error = c.pins.placement_sigma_mm * gauss(rng);
    const double frac = uni(rng);  // where within a count the wheel stood
    const int64_t start = RawCounter(c.rig, c.encoder.start_count, c.rig.encoder.counts_per_rev * 7.3 * uni(rng));
    scan.start_encoder = start;
    const double pin_x = 2.0 * (uni(rng) - 0.5);
    const double meet = offset_mm - error;  // travel at which the pin centre is under the laser
    scan.profiles = renderer.NewBlock();
    const double dt = 1.0 / c.sensor.rate_hz;
    const double t0 = (meet - c.pins.scan_half_length_mm) / c.pins.scan_speed_mm_s;
    const double t1 = (meet + c.pins.scan_half_length_mm) / c.pins.scan_speed_mm_s;
    for (double t = std::max(t0, 0.0); t <= t1; t += dt) {
      const double travel = c.pins.scan_speed_mm_s * t;
      const double d = travel - meet;
      Outline outline;
      if (std::abs(d) < r) outline = RectangleOutline(2.0 * std::sqrt(r * r - d * d), c.pins.height_mm, pin_x);
      SensorPose pose;
      pose.roll_rad = roll;
      renderer.Append(scan.profiles, outline, pose, rng);
      scan.profiles.t_s.push_back(100.0 * k + t);
      scan.profiles.encoder.push_back(RawCounter(c.rig, start, frac + travel / mm_per_count));
    }
    out.truth.pins.placement_error_mm.push_back(error);
    out.truth.pins.peak_counts.push_back(meet / mm_per_count);
    out.pins.scans.push_back(std::move(scan));
  }
}

}  // namespace

SimulatedRun Simulate(const SimConfig& config) {
  SimulatedRun out;
  // Independent streams so that changing one part leaves the others' noise alone.
  std::mt19937_64 seeds(config.seed);
  std::mt19937_64 rng_dynamics(seeds()), rng_profiles(seeds()), rng_log(seeds()), rng_pins(seeds());
  const Timeline tl = RunDynamics(config, rng_dynamics);
  SimulateProfiles(config, tl, rng_profiles, out);
  SimulateLog(config, tl, rng_log, out);
  SimulatePins(config, rng_pins, out);
  out.rig_file = config.rig;
  out.rig_file.offset_counts = config.rig.offset_counts + config.effects.rig_offset_error_counts;
  out.truth.offset_counts = config.rig.offset_counts;
  out.truth.rig_file_offset_counts = out.rig_file.offset_counts;
  out.run.attributes["rig"] = config.rig.name;
  out.run.attributes["material"] = "simulated CF-ABS";
  out.run.attributes["source"] = "bead simulate, seed " + std::to_string(config.seed);
  out.pins.attributes["rig"] = config.rig.name;
  return out;
}

}  // namespace bead::sim
