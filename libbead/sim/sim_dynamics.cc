// RunDynamics (sim_timeline.h): the extruder (voltage -> screw speed ->
// flow, thesis eqs. 21-22, with the screw's PID and the barrel's melt) and
// the wheel (its first-order response to its command, thesis 3.3.3, or
// the feed-forward controller of thesis 4.2) stepped together. The noise
// is drawn in one fixed order (the command, then at each step the screw
// speed's and the flow's), so a config and seed give the same run.
#include <cmath>
#include <numbers>
#include <optional>

#include "libbead/model/feed_forward.h"
#include "libbead/model/lti_response.h"
#include "libbead/sim/barrel.h"
#include "libbead/sim/command_signal.h"
#include "libbead/sim/screw_pid.h"
#include "libbead/sim/sim_timeline.h"

namespace bead::sim {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::size_t Lag(double delay_s, double dt_s) { return static_cast<std::size_t>(std::llround(delay_s / dt_s)); }

// Long enough for the material under the laser at t = 0 to have been laid
// in steady state: the wheel's travel from nozzle to laser at its starting
// speed, and a second more.
double WarmStartTime(const SimConfig& c) {
  const double radius = c.rig.wheel_diameter_mm / 2;
  const double omega0 =
      c.wheel.mode == WheelConfig::Mode::kConstant
          ? c.wheel.surface_speed_mm_s / radius
          : std::max(0.05, c.wheel.gain_rpm_per_v * StepsAt(c.wheel.cmd_levels_v, c.wheel.cmd_durations_s, 0.0) *
                               kTwoPi / 60.0);
  const double travel = kTwoPi * c.rig.offset_counts / c.rig.encoder.counts_per_rev / omega0;
  return -c.dt_s * std::ceil((travel + 1.0 + c.wheel.tau_s * 10) / c.dt_s);
}

// Voltage -> screw speed -> flow, with the PID (its setpoint the command,
// in RPM) and the barrel's melt when configured.
class Extruder {
 public:
  Extruder(const SimConfig& c, Timeline& tl)
      : c_(c),
        to_rpm_(c.extruder.voltage_to_rpm, c.dt_s),
        to_flow_(c.extruder.rpm_to_flow, c.dt_s),
        pid_(c.extruder.pid, c.dt_s),
        rpm_lag_(Lag(c.extruder.voltage_to_rpm.delay_s, c.dt_s)),
        flow_lag_(Lag(c.extruder.rpm_to_flow.delay_s, c.dt_s)),
        noise_alpha_(std::exp(-c.dt_s / 0.2)),
        noise_gain_(std::sqrt((1 + noise_alpha_) / (1 - noise_alpha_))),
        barrel_rng_(c.seed ^ 0xba77e1ULL) {
    if (c.extruder.pid.on) {
      setpoint_rpm_ = tl.command_v;
      const double v0 = c.warm_start ? setpoint_rpm_.front() / c.extruder.voltage_to_rpm.DcGain() : 0.0;
      std::fill(tl.command_v.begin(), tl.command_v.end(), v0);
      pid_.Start(v0);
    }
    if (c.warm_start) {  // in steady state at the first command
      const double v0 = tl.command_v.front();
      rpm_before_ = c.extruder.voltage_to_rpm.DcGain() * v0;
      to_rpm_.Reset(v0);
      to_flow_.Reset(rpm_before_);
    }
    if (c.barrel.record || c.barrel.record_ambient || c.barrel.flow_per_c != 0.0) {
      barrel_.emplace(c.barrel, c.dt_s);
      tl.barrel_c.assign(tl.command_v.size(), 0.0);
      tl.ambient_c.assign(tl.command_v.size(), 0.0);
    }
  }

  void Step(std::size_t i, Timeline& tl, std::mt19937_64& rng) {
    if (c_.extruder.pid.on)
      tl.command_v[i] = pid_.Step(setpoint_rpm_[i], i > 0 ? tl.rpm[i - 1] : setpoint_rpm_[i],
                                  i > 0 ? tl.command_v[i - 1] : tl.command_v[0]);
    const double u_rpm = i >= rpm_lag_ ? tl.command_v[i - rpm_lag_] : (c_.warm_start ? tl.command_v.front() : 0.0);
    tl.rpm[i] = std::max(0.0, to_rpm_.Step(u_rpm) + c_.extruder.rpm_noise * gauss_(rng));
    const double u_flow = i >= flow_lag_ ? tl.rpm[i - flow_lag_] : rpm_before_;
    flow_noise_ = noise_alpha_ * flow_noise_ + (1 - noise_alpha_) * gauss_(rng);
    tl.flow[i] = std::max(0.0, to_flow_.Step(u_flow) * (1.0 + c_.extruder.flow_noise_frac * noise_gain_ * flow_noise_));
    if (barrel_) {
      barrel_->Step(barrel_rng_);
      tl.flow[i] *= barrel_->flow_factor();
      tl.barrel_c[i] = barrel_->reading_c();
      tl.ambient_c[i] = barrel_->ambient_c();
    }
  }

 private:
  const SimConfig& c_;
  model::DiscreteSystem to_rpm_, to_flow_;
  ScrewPid pid_;
  std::vector<double> setpoint_rpm_;
  std::size_t rpm_lag_, flow_lag_;
  double rpm_before_ = 0.0;  // the screw speed before the first sample (the flow's delay)
  double noise_alpha_, noise_gain_, flow_noise_ = 0.0;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  std::optional<Barrel> barrel_;
  std::mt19937_64 barrel_rng_;
};

// The wheel: its command (held steps, or the feed-forward controller at its
// own rate on noise-free models), its first-order response, and the
// surface speed under the nozzle of an eccentric wheel.
class Wheel {
 public:
  explicit Wheel(const SimConfig& c) : c_(c), radius_(c.rig.wheel_diameter_mm / 2), lag_(Lag(c.wheel.delay_s, c.dt_s)) {
    if (c.wheel.mode == WheelConfig::Mode::kFeedForward) {
      model::WheelModel wheel{c.wheel.gain_rpm_per_v, c.wheel.tau_s, c.wheel.delay_s, radius_};
      model::FeedForwardOptions fo;
      fo.target_area_mm2 = c.wheel.target_area_mm2;
      fo.rate_hz = c.wheel.controller_rate_hz;
      feed_forward_.emplace(c.extruder.voltage_to_rpm, c.extruder.rpm_to_flow, wheel, fo);
      ticks_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / (fo.rate_hz * c.dt_s))));
    }
    rpm_ = c.wheel.mode == WheelConfig::Mode::kConstant ? c.wheel.surface_speed_mm_s / radius_ * 60.0 / kTwoPi : 0.0;
    if (c.warm_start && c.wheel.mode == WheelConfig::Mode::kCommanded) {  // in steady state at its first command
      cmd_before_ = StepsAt(c.wheel.cmd_levels_v, c.wheel.cmd_durations_s, 0.0);
      rpm_ = c.wheel.gain_rpm_per_v * cmd_before_;
    }
  }

  void Step(std::size_t i, double t, Timeline& tl) {
    switch (c_.wheel.mode) {
      case WheelConfig::Mode::kConstant:
        break;
      case WheelConfig::Mode::kCommanded:
        tl.wheel_cmd_v[i] = StepsAt(c_.wheel.cmd_levels_v, c_.wheel.cmd_durations_s, t);
        break;
      case WheelConfig::Mode::kFeedForward:
        tl.wheel_cmd_v[i] = i % ticks_ == 0 ? feed_forward_->Step(tl.command_v[i]) : tl.wheel_cmd_v[i - 1];
        break;
    }
    if (c_.wheel.mode != WheelConfig::Mode::kConstant) {
      const double v_in = i >= lag_ ? tl.wheel_cmd_v[i - lag_] : cmd_before_;
      const double a = std::exp(-c_.dt_s / c_.wheel.tau_s);
      rpm_ = a * rpm_ + (1 - a) * c_.wheel.gain_rpm_per_v * v_in;
    }
    const double omega = std::max(0.0, rpm_) * kTwoPi / 60.0;
    if (i > 0) tl.angle[i] = tl.angle[i - 1] + omega * c_.dt_s;
    // Eccentricity: the radius under the nozzle varies with the angle.
    tl.speed[i] = omega * (radius_ + c_.effects.eccentricity_mm * std::cos(tl.angle[i]));
    tl.area[i] = tl.speed[i] > 1e-9 ? tl.flow[i] / tl.speed[i] : 0.0;
  }

 private:
  const SimConfig& c_;
  double radius_;
  std::size_t lag_, ticks_ = 1;
  std::optional<model::FeedForward> feed_forward_;
  double rpm_ = 0.0, cmd_before_ = 0.0;  // the command before the first sample (the delay)
};

}  // namespace

Timeline RunDynamics(const SimConfig& c, std::mt19937_64& rng) {
  Timeline tl;
  tl.dt = c.dt_s;
  if (c.warm_start) tl.t0 = WarmStartTime(c);
  const std::size_t n = static_cast<std::size_t>(std::ceil((c.duration_s - tl.t0) / c.dt_s)) + 1;
  tl.command_v = CommandSeries(c.extruder.command, c.dt_s, n, rng, tl.t0, c.warm_start);
  for (auto* v : {&tl.wheel_cmd_v, &tl.rpm, &tl.flow, &tl.angle, &tl.speed, &tl.area}) v->assign(n, 0.0);
  Extruder extruder(c, tl);
  Wheel wheel(c);
  for (std::size_t i = 0; i < n; ++i) {
    extruder.Step(i, tl, rng);
    wheel.Step(i, tl.Time(static_cast<double>(i)), tl);
  }
  return tl;
}

}  // namespace bead::sim
