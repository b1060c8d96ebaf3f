#include "libbead/sim/rig_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

#include "libbead/sim/bead_shapes.h"
#include "libbead/sim/command_signal.h"
#include "libbead/sim/sensor_model.h"
#include "libbead/sim/sim_timeline.h"

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
