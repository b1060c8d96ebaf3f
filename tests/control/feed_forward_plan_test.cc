// The thesis' feed-forward as a plan (control/feed_forward_plan.h): on the
// models it was planned with, the area holds to the models' own rounding;
// played on the digital twin (its extruder noisy, its wheel's response
// its own), the laid bead's area varies several times less than under a
// constant wheel laying the same mean area. The thesis measured about six
// times less variation on its rig (its Table 4); the twin's figure is
// printed beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "libbead/control/feed_forward_plan.h"
#include "libbead/sim/command_signal.h"
#include "libbead/sim/rig_simulator.h"

namespace bead::control {
namespace {

// The extruder steps of testdata/configs/feedforward.yaml.
sim::CommandConfig Steps() {
  sim::CommandConfig c;
  c.kind = sim::CommandConfig::Kind::kSteps;
  c.levels_v = {3.0, 4.0, 2.5, 3.5};
  c.durations_s = {5, 5, 5, 5};
  c.start_s = 0.5;
  return c;
}

// RMS deviation of the laid area from its mean, relative to the mean, over
// the profiles that measured a bead after the first second.
double AreaVariation(const sim::SimulatedRun& r) {
  const auto& a = r.truth.profiles.area_true_mm2;
  const auto& t = r.truth.profiles.t_s;
  double m = 0, n = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (t[i] > 2.0 && a[i] > 0) m += a[i], ++n;
  m /= n;
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (t[i] > 2.0 && a[i] > 0) s += (a[i] - m) * (a[i] - m);
  return std::sqrt(s / n) / m;
}

TEST(FeedForwardPlan, HoldsTheAreaOnItsModelsAndOnTheTwin) {
  sim::SimConfig c;
  c.seed = 4;
  c.duration_s = 22;
  c.extruder.command = Steps();
  c.warm_start = true;  // the extruder at its first level before the steps
  // The plan: the extruder command at 100 Hz, planned with the twin's own
  // models (what a perfect identification would give).
  std::vector<double> t, v;
  const sim::CommandConfig& cmd = c.extruder.command;
  for (int i = 0; i <= 2200; ++i) {
    t.push_back(0.01 * i);
    v.push_back(t.back() < cmd.start_s ? sim::BaseLevel(cmd)
                                       : sim::StepsAt(cmd.levels_v, cmd.durations_s, t.back() - cmd.start_s));
  }
  model::WheelModel wheel{c.wheel.gain_rpm_per_v, c.wheel.tau_s, c.wheel.delay_s, c.rig.wheel_diameter_mm / 2};
  model::FeedForwardOptions o;
  o.target_area_mm2 = 14.0;
  const WheelPlan p = PlanWheel(t, v, c.extruder.voltage_to_rpm, c.extruder.rpm_to_flow, wheel, o);
  // On its own models the plan holds the area to a controller tick's
  // change of the flow (the held command): under 1 %.
  EXPECT_LT(p.rms_rel_planned, 0.01);
  EXPECT_GT(p.rms_rel_constant, 0.10);
  // Played on the twin (the wheel commanded tick by tick) ...
  sim::SimConfig played = c;
  played.wheel.mode = sim::WheelConfig::Mode::kCommanded;
  played.wheel.cmd_levels_v = p.wheel_cmd_v;
  played.wheel.cmd_durations_s.assign(p.wheel_cmd_v.size(), 0.01);
  const double fed = AreaVariation(sim::Simulate(played));
  // ... and against a constant wheel at the speed that lays 14 mm^2 at the
  // plan's mean flow.
  double mean_flow = 0;
  for (double q : p.flow_mm3_s) mean_flow += q / static_cast<double>(p.flow_mm3_s.size());
  sim::SimConfig constant = c;
  constant.wheel.mode = sim::WheelConfig::Mode::kConstant;
  constant.wheel.surface_speed_mm_s = mean_flow / 14.0;
  const double plain = AreaVariation(sim::Simulate(constant));
  std::printf("twin: area varies %.2f %% fed forward, %.2f %% with a constant wheel: %.1f times less (thesis: ~6)\n",
              100 * fed, 100 * plain, plain / fed);
  // The twin's flow carries 1 % of low-passed noise no feed-forward can
  // know of: the fed-forward variation cannot go below it, and the
  // constant wheel's is the steps' own (about 18 %); the thesis' six times
  // is the figure to beat.
  EXPECT_GT(plain / fed, 6.0);
  EXPECT_LT(fed, 3 * c.extruder.flow_noise_frac);
}

}  // namespace
}  // namespace bead::control
