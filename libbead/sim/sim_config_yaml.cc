// YAML reading of SimConfig. Layout (every key optional):
//   seed, duration_s, dt_s, log_rate_hz, warm_start,
//   rig: {name, counts_per_rev, bits, direction, diameter_mm, offset_counts,
//         reference_areas_mm, laser_origin_mm},
//   extruder: {command: {kind, base_v, levels_v, durations_s, amplitude_v, bit_time_s, start_s, stop_s},
//              voltage_to_rpm: {num, den, delay_s}, rpm_to_flow: {num, den, delay_s},
//              rpm_noise, flow_noise_frac, pid: {kp, ki, kd, derivative_filter_s, rate_hz, max_v}},
//   wheel: {mode, surface_speed_mm_s, target_area_mm2, controller_rate_hz, gain_rpm_per_v, tau_s, delay_s,
//           cmd_levels_v, cmd_durations_s, cmd_csv (a wheel command CSV to play,
//           t_s and wheel_cmd_v as bead feedforward writes it; relative to this file)},
//   encoder: {start_count, missed_read_prob},
//   bead: {shape, aspect, bottom_radius_frac, top_radius_frac, exponent, bottom_exponent, center_lift_frac,
//          center_wander_mm, center_wander_period_s, outline_vertices},
//   sensor: {rate_hz, points, x_min_mm, x_max_mm, fan, z_sigma_mm, z_quantum_mm, dropout_prob,
//            spike_prob, spike_mm, dropped_profile_prob, roll_deg, runout_mm},
//   pins: {scans, placement_sigma_mm, diameter_mm, height_mm, scan_speed_mm_s, scan_half_length_mm},
//   effects: {eccentricity_mm, shrink_frac, shrink_tau_s, rig_offset_error_counts, sensor_latency_s},
//   barrel: {record, control (bang_bang | pid), setpoint_c, band_c, heater_c, ambient_c, wall_tau_s,
//            sensor_tau_s, melt_tau_s, noise_c, kp, ki, kd, flow_per_c, record_ambient}
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/yaml_text.h"
#include "libbead/sim/sim_config.h"
#include "libbead/sim/sim_yaml_reader.h"

namespace bead::sim {
namespace {

void ParseBarrel(const YAML::Node& root, const Reader& r, BarrelConfig& b) {
  const YAML::Node ba =
      r.Section(root, "barrel",
                {"record", "control", "setpoint_c", "band_c", "heater_c", "ambient_c", "wall_tau_s", "sensor_tau_s",
                 "melt_tau_s", "noise_c", "kp", "ki", "kd", "flow_per_c", "record_ambient"});
  r.GetBool(ba, "barrel.", "record", b.record);
  r.GetBool(ba, "barrel.", "record_ambient", b.record_ambient);
  if (ba && ba["control"]) {
    const std::string k = r.Text(ba["control"], "barrel.control");
    if (k == "bang_bang")
      b.control = BarrelConfig::Control::kBangBang;
    else if (k == "pid")
      b.control = BarrelConfig::Control::kPid;
    else
      r.Fail(ba["control"], "barrel.control", "must be bang_bang or pid, not '" + k + "'");
  }
  r.Get(ba, "barrel.", "setpoint_c", b.setpoint_c, -50, 600);
  r.Get(ba, "barrel.", "band_c", b.band_c, 0, 100);
  r.Get(ba, "barrel.", "heater_c", b.heater_c, -50, 1000);
  r.Get(ba, "barrel.", "ambient_c", b.ambient_c, -50, 600);
  r.Get(ba, "barrel.", "wall_tau_s", b.wall_tau_s, 0.01, 1e5);
  r.Get(ba, "barrel.", "sensor_tau_s", b.sensor_tau_s, 1e-3, 1e4);
  r.Get(ba, "barrel.", "melt_tau_s", b.melt_tau_s, 1e-3, 1e4);
  r.Get(ba, "barrel.", "noise_c", b.noise_c, 0, 100);
  r.Get(ba, "barrel.", "kp", b.kp, 0, 1e3);
  r.Get(ba, "barrel.", "ki", b.ki, 0, 1e3);
  r.Get(ba, "barrel.", "kd", b.kd, 0, 1e3);
  r.Get(ba, "barrel.", "flow_per_c", b.flow_per_c, -1, 1);
  if (!(b.heater_c > b.setpoint_c && b.setpoint_c > b.ambient_c))
    r.Fail(ba, "barrel", "needs ambient_c < setpoint_c < heater_c (the heater must be able to reach the setpoint)");
}

// The wheel command of a CSV with columns t_s and wheel_cmd_v (what bead
// feedforward writes), as held steps from t = 0: the first level also
// before its first time.
void ReadWheelCommand(const std::string& path, WheelConfig& w) {
  CsvReader csv(path);
  const std::vector<std::string> header = csv.Header({"t_s"}, "wheel command CSV (t_s, ..., wheel_cmd_v)");
  const auto col = std::find(header.begin(), header.end(), "wheel_cmd_v");
  if (col == header.end()) csv.Fail("no column wheel_cmd_v");
  const auto k = static_cast<std::size_t>(col - header.begin());
  std::vector<double> t, v;
  while (csv.Next()) {
    t.push_back(csv.Double(0, "t_s"));
    v.push_back(csv.Double(k, "wheel_cmd_v"));
    if (!std::isfinite(t.back()) || !std::isfinite(v.back())) csv.Fail("time and command must be numbers");
    if (t.size() > 1 && !(t.back() > t[t.size() - 2])) csv.Fail("time must increase");
  }
  if (t.empty()) throw Error(Located(path, "", "no command rows"));
  w.cmd_levels_v = v;
  w.cmd_durations_s.clear();
  for (std::size_t i = 0; i + 1 < t.size(); ++i) w.cmd_durations_s.push_back(t[i + 1] - t[i]);
  w.cmd_durations_s.push_back(1e9);
  if (t[0] > 0) w.cmd_durations_s[0] += t[0];
}

// rig: the rig file's keys, checked by the rig file's rules (core/rig.h).
void ParseRig(const YAML::Node& root, const Reader& r, SimConfig& c) {
  const YAML::Node rig = r.Section(root, "rig",
                                   {"name", "counts_per_rev", "bits", "direction", "diameter_mm", "offset_counts",
                                    "reference_areas_mm", "laser_origin_mm"});
  if (rig.IsDefined()) {
    if (rig["name"].IsDefined()) c.rig.name = r.Text(rig["name"], "rig.name");
    r.Get(rig, "rig.", "counts_per_rev", c.rig.encoder.counts_per_rev, 1, 1e9);
    r.GetInt(rig, "rig.", "bits", c.rig.encoder.bits, 0, 64);
    r.GetInt(rig, "rig.", "direction", c.rig.encoder.direction, -1, 1);
    r.Get(rig, "rig.", "diameter_mm", c.rig.wheel_diameter_mm, 1, 1e5);
    r.Get(rig, "rig.", "offset_counts", c.rig.offset_counts, 0, 1e9);
    std::vector<double> areas;
    if (rig["reference_areas_mm"].IsDefined()) {
      const YAML::Node a = rig["reference_areas_mm"];
      if (!a.IsSequence() || a.size() != 2 || a[0].size() != 2 || a[1].size() != 2)
        r.Fail(a, "rig.reference_areas_mm", "must be [[x0, x1], [x2, x3]]");
      c.rig.reference_left = {a[0][0].as<double>(), a[0][1].as<double>()};
      c.rig.reference_right = {a[1][0].as<double>(), a[1][1].as<double>()};
    }
    if (rig["laser_origin_mm"].IsDefined()) {
      std::vector<double> o;
      r.GetList(rig, "rig.", "laser_origin_mm", o);
      if (o.size() != 2) r.Fail(rig["laser_origin_mm"], "rig.laser_origin_mm", "must be [x, z]");
      c.rig.laser_origin = LaserOrigin{o[0], o[1]};
    }
  }
  // The rig file's rules (core/rig.h), keys named as this file spells them.
  if (std::string key, error; !IsValid(c.rig, true, &key, &error)) {
    const std::string leaf = key.substr(key.rfind('.') + 1);
    const std::string here = leaf.rfind("reference_areas_mm", 0) == 0 ? "reference_areas_mm" : leaf;
    r.Fail(rig.IsDefined() && rig[here].IsDefined() ? rig[here] : root, "rig." + here, error + " (" + key + ")");
  }
}

// extruder: its command, transfer functions, noise and the screw's PID.
void ParseExtruder(const YAML::Node& root, const Reader& r, SimConfig& c) {
  const YAML::Node ex =
      r.Section(root, "extruder", {"command", "voltage_to_rpm", "rpm_to_flow", "rpm_noise", "flow_noise_frac", "pid"});
  if (ex.IsDefined()) {
    const YAML::Node cmd = r.Section(
        ex, "command", {"kind", "base_v", "levels_v", "durations_s", "amplitude_v", "bit_time_s", "start_s", "stop_s"});
    auto& k = c.extruder.command;
    using K = CommandConfig::Kind;
    r.GetEnum<K>(cmd, "extruder.command.", "kind", k.kind,
                 {{"constant", K::kConstant}, {"steps", K::kSteps}, {"prbs", K::kPrbs}, {"gaussian", K::kGaussian}});
    r.Get(cmd, "extruder.command.", "base_v", k.base_v, -10, 10);
    r.GetList(cmd, "extruder.command.", "levels_v", k.levels_v);
    r.GetList(cmd, "extruder.command.", "durations_s", k.durations_s);
    if (k.levels_v.size() != k.durations_s.size())
      r.Fail(cmd, "extruder.command", "levels_v and durations_s must have the same length");
    r.Get(cmd, "extruder.command.", "amplitude_v", k.amplitude_v, 0, 10);
    r.Get(cmd, "extruder.command.", "bit_time_s", k.bit_time_s, 1e-3, 1e4);
    r.Get(cmd, "extruder.command.", "start_s", k.start_s, 0, 1e5);
    r.Get(cmd, "extruder.command.", "stop_s", k.stop_s, -1, 1e5);
    r.GetTf(ex, "extruder.", "voltage_to_rpm", c.extruder.voltage_to_rpm);
    r.GetTf(ex, "extruder.", "rpm_to_flow", c.extruder.rpm_to_flow);
    r.Get(ex, "extruder.", "rpm_noise", c.extruder.rpm_noise, 0, 1e3);
    r.Get(ex, "extruder.", "flow_noise_frac", c.extruder.flow_noise_frac, 0, 1);
    if (ex["pid"]) {
      const YAML::Node pid = r.Section(ex, "pid", {"kp", "ki", "kd", "derivative_filter_s", "rate_hz", "max_v"});
      auto& p = c.extruder.pid;
      p.on = true;
      r.Get(pid, "extruder.pid.", "kp", p.kp, -1e6, 1e6);
      r.Get(pid, "extruder.pid.", "ki", p.ki, -1e6, 1e6);
      r.Get(pid, "extruder.pid.", "kd", p.kd, -1e6, 1e6);
      r.Get(pid, "extruder.pid.", "derivative_filter_s", p.derivative_filter_s, 0, 1e4);
      r.Get(pid, "extruder.pid.", "rate_hz", p.rate_hz, 1e-3, 1e6);
      r.Get(pid, "extruder.pid.", "max_v", p.max_v, 0, 1e3);
    }
  }
}

// wheel: its mode, speed, dynamics and command (levels or a CSV).
void ParseWheel(const YAML::Node& root, const Reader& r, SimConfig& c) {
  const YAML::Node wh = r.Section(root, "wheel",
                                  {"mode", "surface_speed_mm_s", "target_area_mm2", "controller_rate_hz",
                                   "gain_rpm_per_v", "tau_s", "delay_s", "cmd_levels_v", "cmd_durations_s", "cmd_csv"});
  using M = WheelConfig::Mode;
  r.GetEnum<M>(wh, "wheel.", "mode", c.wheel.mode,
               {{"constant", M::kConstant}, {"commanded", M::kCommanded}, {"feedforward", M::kFeedForward}});
  r.Get(wh, "wheel.", "surface_speed_mm_s", c.wheel.surface_speed_mm_s, 1, 1e4);
  r.Get(wh, "wheel.", "target_area_mm2", c.wheel.target_area_mm2, 0.01, 1e4);
  r.Get(wh, "wheel.", "controller_rate_hz", c.wheel.controller_rate_hz, 1, 1e5);
  r.Get(wh, "wheel.", "gain_rpm_per_v", c.wheel.gain_rpm_per_v, 1e-3, 1e4);
  r.Get(wh, "wheel.", "tau_s", c.wheel.tau_s, 1e-4, 100);
  r.Get(wh, "wheel.", "delay_s", c.wheel.delay_s, 0, 10);
  r.GetList(wh, "wheel.", "cmd_levels_v", c.wheel.cmd_levels_v);
  r.GetList(wh, "wheel.", "cmd_durations_s", c.wheel.cmd_durations_s);
  if (wh.IsDefined() && wh["cmd_csv"]) {
    // A command to play (bead feedforward -o): relative to this file.
    const std::string rel = r.Text(wh["cmd_csv"], "wheel.cmd_csv");
    const std::filesystem::path csv = std::filesystem::path(rel).is_absolute()
                                          ? std::filesystem::path(rel)
                                          : std::filesystem::path(r.file()).parent_path() / rel;
    ReadWheelCommand(csv.string(), c.wheel);
  }
}

// encoder, bead and sensor.
void ParseEncoderBeadSensor(const YAML::Node& root, const Reader& r, SimConfig& c) {
  const YAML::Node en = r.Section(root, "encoder", {"start_count", "missed_read_prob"});
  r.GetInt(en, "encoder.", "start_count", c.encoder.start_count, 0, 9.0e15);
  r.Get(en, "encoder.", "missed_read_prob", c.encoder.missed_read_prob, 0, 0.5);

  const YAML::Node bd =
      r.Section(root, "bead",
                {"shape", "aspect", "bottom_radius_frac", "top_radius_frac", "exponent", "bottom_exponent",
                 "center_lift_frac", "center_wander_mm", "center_wander_period_s", "outline_vertices"});
  using S = BeadConfig::Shape;
  r.GetEnum<S>(
      bd, "bead.", "shape", c.bead.shape,
      {{"rounded_rectangle", S::kRoundedRectangle}, {"superellipse", S::kSuperellipse}, {"parabola", S::kParabola}});
  r.Get(bd, "bead.", "aspect", c.bead.aspect, 0.2, 20);
  r.Get(bd, "bead.", "bottom_radius_frac", c.bead.bottom_radius_frac, 0, 0.5);
  r.Get(bd, "bead.", "top_radius_frac", c.bead.top_radius_frac, 0, 0.5);
  r.Get(bd, "bead.", "exponent", c.bead.exponent, 1.2, 20);
  r.Get(bd, "bead.", "bottom_exponent", c.bead.bottom_exponent, 0, 20);
  r.Get(bd, "bead.", "center_lift_frac", c.bead.center_lift_frac, 0, 0.95);
  r.Get(bd, "bead.", "center_wander_mm", c.bead.center_wander_mm, 0, 20);
  r.Get(bd, "bead.", "center_wander_period_s", c.bead.center_wander_period_s, 0.01, 1e5);
  r.GetInt(bd, "bead.", "outline_vertices", c.bead.outline_vertices, 8, 10000);

  const YAML::Node se =
      r.Section(root, "sensor",
                {"rate_hz", "points", "x_min_mm", "x_max_mm", "fan", "z_sigma_mm", "z_quantum_mm", "dropout_prob",
                 "spike_prob", "spike_mm", "dropped_profile_prob", "roll_deg", "runout_mm"});
  auto& s = c.sensor;
  r.Get(se, "sensor.", "rate_hz", s.rate_hz, 1, 100000);
  r.GetInt(se, "sensor.", "points", s.points, 16, 100000);
  r.Get(se, "sensor.", "x_min_mm", s.x_min_mm, -1e4, 1e4);
  r.Get(se, "sensor.", "x_max_mm", s.x_max_mm, -1e4, 1e4);
  if (!(s.x_max_mm > s.x_min_mm)) r.Fail(se, "sensor", "x_max_mm must exceed x_min_mm");
  r.GetBool(se, "sensor.", "fan", s.fan);
  r.Get(se, "sensor.", "z_sigma_mm", s.z_sigma_mm, 0, 10);
  r.Get(se, "sensor.", "z_quantum_mm", s.z_quantum_mm, 0, 10);
  r.Get(se, "sensor.", "dropout_prob", s.dropout_prob, 0, 1);
  r.Get(se, "sensor.", "spike_prob", s.spike_prob, 0, 1);
  r.Get(se, "sensor.", "spike_mm", s.spike_mm, 0, 100);
  r.Get(se, "sensor.", "dropped_profile_prob", s.dropped_profile_prob, 0, 1);
  r.Get(se, "sensor.", "roll_deg", s.roll_deg, -45, 45);
  r.Get(se, "sensor.", "runout_mm", s.runout_mm, 0, 10);
}

// pins and effects.
void ParsePinsAndEffects(const YAML::Node& root, const Reader& r, SimConfig& c) {
  const YAML::Node pi =
      r.Section(root, "pins",
                {"scans", "placement_sigma_mm", "diameter_mm", "height_mm", "scan_speed_mm_s", "scan_half_length_mm"});
  r.GetInt(pi, "pins.", "scans", c.pins.scans, 0, 1000);
  r.Get(pi, "pins.", "placement_sigma_mm", c.pins.placement_sigma_mm, 0, 100);
  r.Get(pi, "pins.", "diameter_mm", c.pins.diameter_mm, 0.1, 100);
  r.Get(pi, "pins.", "height_mm", c.pins.height_mm, 0.1, 100);
  r.Get(pi, "pins.", "scan_speed_mm_s", c.pins.scan_speed_mm_s, 0.01, 1e4);
  r.Get(pi, "pins.", "scan_half_length_mm", c.pins.scan_half_length_mm, 0.5, 1e3);

  const YAML::Node ef =
      r.Section(root, "effects",
                {"eccentricity_mm", "shrink_frac", "shrink_tau_s", "rig_offset_error_counts", "sensor_latency_s"});
  r.Get(ef, "effects.", "eccentricity_mm", c.effects.eccentricity_mm, 0, 50);
  r.Get(ef, "effects.", "shrink_frac", c.effects.shrink_frac, 0, 0.9);
  r.Get(ef, "effects.", "shrink_tau_s", c.effects.shrink_tau_s, 1e-3, 1e4);
  r.Get(ef, "effects.", "rig_offset_error_counts", c.effects.rig_offset_error_counts, -1e9, 1e9);
  r.Get(ef, "effects.", "sensor_latency_s", c.effects.sensor_latency_s, -10, 10);
}

void Parse(const YAML::Node& root, const Reader& r, SimConfig& c) {
  if (!root.IsMap()) r.Fail(root, "", "a simulation config must be a YAML mapping");
  const std::set<std::string> top = {"seed",  "duration_s", "dt_s", "log_rate_hz", "warm_start", "rig",     "extruder",
                                     "wheel", "encoder",    "bead", "sensor",      "pins",       "effects", "barrel"};
  for (const auto& kv : root)
    if (const std::string k = r.Text(kv.first, "<key>"); !top.count(k)) r.Fail(kv.first, k, "unknown key (misspelt?)");
  r.GetInt(root, "", "seed", c.seed, 0, 9.0e15);
  r.Get(root, "", "duration_s", c.duration_s, 0.1, 36000);
  r.Get(root, "", "dt_s", c.dt_s, 1e-5, 0.01);
  r.Get(root, "", "log_rate_hz", c.log_rate_hz, 1, 100000);
  r.GetBool(root, "", "warm_start", c.warm_start);

  ParseRig(root, r, c);
  ParseExtruder(root, r, c);
  ParseWheel(root, r, c);
  ParseEncoderBeadSensor(root, r, c);
  ParsePinsAndEffects(root, r, c);
  ParseBarrel(root, r, c.barrel);
}

}  // namespace

SimConfig ParseSimConfig(const std::string& text, const std::string& name) {
  const YAML::Node root = ParseYamlText(text, name);
  SimConfig c;
  if (root.IsNull()) return c;
  try {
    Parse(root, Reader(name), c);
  } catch (const YAML::Exception& e) {  // what the checks above did not foresee still names the file
    throw Error(Located(name, "line " + std::to_string(e.mark.line + 1), e.msg));
  }
  return c;
}

SimConfig ReadSimConfig(const std::string& path) {
  return ParseSimConfig(ReadTextFile(path, "simulation config"), path);
}

}  // namespace bead::sim
