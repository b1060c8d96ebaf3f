// explain on runs of the digital twin with one effect switched on in the
// simulation and not declared to the analysis. The model of flow from
// screw RPM comes from a clean run of the same rig (the calibration run a
// user would have), as `bead explain --model` takes it. For every effect
// the twin offers, explain must find it, recover its parameter within 1.5
// times its 95 % half-width (about 3 standard deviations: a correct
// estimate fails with probability 0.3 %), and lower the error; on a clean
// run it adds nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "libbead/explain/explain_loop.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/model/identify.h"
#include "libbead/profile/measure_block.h"
#include "libbead/sim/rig_simulator.h"

namespace bead::explain {
namespace {

// 24 s of PRBS on the extruder; the wheel commanded in steps so that its
// speed (and so the time from nozzle to laser) changes, which is what lets
// a position shift be told from a time shift.
sim::SimConfig Base(uint64_t seed) {
  sim::SimConfig c;
  c.seed = seed;
  c.duration_s = 24.0;
  c.sensor.points = 160;
  c.extruder.command.kind = sim::CommandConfig::Kind::kPrbs;
  c.extruder.command.base_v = 3.2;
  c.extruder.command.amplitude_v = 0.8;
  c.extruder.command.bit_time_s = 0.5;
  c.wheel.mode = sim::WheelConfig::Mode::kCommanded;
  c.wheel.cmd_levels_v = {6.0, 4.5, 7.5};
  c.wheel.cmd_durations_s = {8.0, 8.0, 8.0};
  return c;
}

struct Pipeline {
  sim::SimulatedRun sim;
  std::vector<BeadGeometry> geometry;
  FlowResult flow;
};

std::unique_ptr<Pipeline> RunPipeline(const sim::SimConfig& c) {
  auto p = std::make_unique<Pipeline>();
  p->sim = sim::Simulate(c);
  const ProfileBlock& b = p->sim.run.profiles;
  p->geometry = MeasureProfiles(b.size(), [&](std::size_t i) { return b.view(i); }, p->sim.rig_file.reference_left,
                                p->sim.rig_file.reference_right, {});
  p->flow = ComputeFlow(p->sim.rig_file, b, p->geometry, *p->sim.run.log);
  return p;
}

// The calibration run's model (with its operating point), identified once.
const model::IdentifiedModel& CalibrationModel() {
  static const model::IdentifiedModel model = [] {
    const auto p = RunPipeline(Base(900));
    std::vector<double> t, u, y;
    for (const auto& s : p->flow.samples)
      if (s.valid) t.push_back(s.t_s), u.push_back(s.screw_rpm), y.push_back(s.flow_mm3_s);
    model::IdentifyOptions o;
    o.poles = 2;
    o.zeros = 2;
    const auto m = model::IdentifyTransferFunction(t, u, y, o);
    EXPECT_TRUE(m.ok) << m.reason;
    return m;
  }();
  return model;
}

struct Outcome {
  std::unique_ptr<Pipeline> run;
  RunSeries series;
  ExplainReport report;
};

Outcome ExplainRun(const sim::SimConfig& c) {
  Outcome o;
  o.run = RunPipeline(c);
  const Rig& rig = o.run->sim.rig_file;
  o.series = MakeRunSeries(rig, o.run->sim.run.profiles, o.run->geometry, *o.run->sim.run.log, o.run->flow,
                           CalibrationModel().tf, CalibrationModel().offset);
  ExplainOptions options;
  options.catalogue.has_wheel = true;
  options.catalogue.position_range_counts = rig.encoder.counts_per_rev / 20.0;
  o.report = Explain(o.series.data, options);
  return o;
}

const AddedEffect* Find(const ExplainReport& r, const std::string& name) {
  for (const auto& e : r.effects_added)
    if (e.name == name) return &e;
  return nullptr;
}

double Param(const AddedEffect& e, const std::string& name, double* ci) {
  for (const auto& p : e.parameters)
    if (p.name == name) {
      *ci = p.ci95;
      return p.value;
    }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

std::string Names(const ExplainReport& r) {
  std::string s = "added:";
  for (const auto& e : r.effects_added) {
    s += " " + e.name + " [";
    for (const auto& p : e.parameters) s += p.name + "=" + std::to_string(p.value) + "+-" + std::to_string(p.ci95) + " ";
    s += "rms " + std::to_string(e.rms_before) + " -> " + std::to_string(e.rms_after) + "]";
  }
  s += "; tried (round, name, BIC drop, held-out F):";
  for (const auto& c : r.candidates)
    s += " (" + std::to_string(c.round) + " " + c.name + " " + std::to_string(c.bic_drop) + " " + std::to_string(c.heldout_f) +
         " " + std::to_string(c.surrogate_f) + ")";
  return s;
}

TEST(ExplainRun, CleanRunGetsNothingAndItsOffsetIsTheRigFiles) {
  const Outcome o = ExplainRun(Base(11));
  EXPECT_TRUE(o.report.effects_added.empty()) << Names(o.report);
  ASSERT_TRUE(o.report.position_shift_estimated);
  EXPECT_NEAR(o.report.position_shift_counts, 0.0, 1.5 * o.report.position_shift_ci95_counts);
}

TEST(ExplainRun, FindsAWrongEncoderOffset) {
  sim::SimConfig c = Base(12);
  c.effects.rig_offset_error_counts = 400.0;  // the rig file says 400 counts too many
  const Outcome o = ExplainRun(c);
  const AddedEffect* e = Find(o.report, "encoder_offset");
  ASSERT_NE(e, nullptr) << Names(o.report);
  EXPECT_LT(e->rms_after, e->rms_before);
  // The run's own offset is the true one.
  const double true_offset = o.run->sim.truth.offset_counts;
  const double from_run = o.run->sim.rig_file.offset_counts + o.report.position_shift_counts;
  EXPECT_NEAR(from_run, true_offset, 1.5 * o.report.position_shift_ci95_counts);
  std::printf("offset: rig file %.1f, from the run %.1f +- %.1f, true %.1f counts; RMS %.2f -> %.2f mm^3/s\n",
              o.run->sim.rig_file.offset_counts, from_run, o.report.position_shift_ci95_counts, true_offset,
              e->rms_before, e->rms_after);
  EXPECT_LT(o.report.position_shift_ci95_counts, 100.0);
}

TEST(ExplainRun, FindsWheelEccentricity) {
  sim::SimConfig c = Base(13);
  c.effects.eccentricity_mm = 1.5;
  const Outcome o = ExplainRun(c);
  const AddedEffect* e = Find(o.report, "once_per_rev[wheel]");
  ASSERT_NE(e, nullptr) << Names(o.report);
  // Q measured = v_encoder A = Q (R / (R + e cos angle)): relative amplitude e / R.
  double ci = 0;
  const double amplitude = Param(*e, "amplitude_rel", &ci);
  EXPECT_NEAR(amplitude, c.effects.eccentricity_mm / (c.rig.wheel_diameter_mm / 2), 1.5 * ci);
  std::printf("eccentricity: once per rev %.4f +- %.4f, true e/R %.4f; RMS %.2f -> %.2f mm^3/s\n", amplitude, ci,
              c.effects.eccentricity_mm / (c.rig.wheel_diameter_mm / 2), e->rms_before, e->rms_after);
  EXPECT_LT(e->rms_after, e->rms_before);
}

TEST(ExplainRun, FindsCoolingShrink) {
  sim::SimConfig c = Base(14);
  c.effects.shrink_frac = 0.05;
  c.effects.shrink_tau_s = 0.8;
  const Outcome o = ExplainRun(c);
  const AddedEffect* e = Find(o.report, "cooling_shrink");
  ASSERT_NE(e, nullptr) << Names(o.report);
  // The shrink at the mean time from nozzle to laser: 0.05 (1 - exp(-m / 0.8)).
  double m = 0;
  for (double dt : o.series.data.time_to_laser_s) m += dt;
  m /= o.series.data.time_to_laser_s.size();
  double ci_shrink = 0, ci_tau = 0;
  const double shrink = Param(*e, "shrink_at_mean_frac", &ci_shrink), tau = Param(*e, "tau_s", &ci_tau);
  EXPECT_NEAR(shrink, 0.05 * (1 - std::exp(-m / 0.8)), 1.5 * ci_shrink) << Names(o.report);
  EXPECT_LT(ci_shrink, 0.25 * shrink);  // pinned down ...
  EXPECT_NEAR(tau, 0.8, 1.5 * ci_tau);  // ... where the curvature, on 0.5-1 s to the laser, is not
  std::printf("shrink: at the mean time to laser %.4f +- %.4f (true %.4f), tau %.2f +- %.2f s (true 0.8); RMS %.2f -> %.2f\n",
              shrink, ci_shrink, 0.05 * (1 - std::exp(-m / 0.8)), tau, ci_tau, e->rms_before, e->rms_after);
  EXPECT_LT(e->rms_after, e->rms_before);
}

TEST(ExplainRun, SensorLatencyShowsInTheTimeStampsNotInTheFlow) {
  sim::SimConfig c = Base(15);
  c.effects.sensor_latency_s = 0.03;
  const Outcome o = ExplainRun(c);
  EXPECT_NEAR(o.series.timestamp_offset_s, 0.03, std::max(1.5 * o.series.timestamp_offset_ci95_s, 1e-4));
  std::printf("latency: time stamps %.5f +- %.5f s late (true 0.03)\n", o.series.timestamp_offset_s,
              o.series.timestamp_offset_ci95_s);
  // The flow uses the profile's own latched count: its flow is a clean
  // run's, with nothing to add and no misalignment to blame on the latency.
  EXPECT_TRUE(o.report.effects_added.empty()) << Names(o.report);
  EXPECT_NEAR(o.report.position_shift_counts, 0.0, 1.5 * o.report.position_shift_ci95_counts);
}

}  // namespace
}  // namespace bead::explain
