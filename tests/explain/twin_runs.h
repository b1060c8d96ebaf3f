// The digital twin's runs for explain's tests: a run with an effect
// switched on and not declared, measured and explained with the model of
// a clean calibration run of the same rig, as `bead explain --model` takes
// it; and the flow held against the twin's truth.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "libbead/explain/explain_loop.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/flow/measured_flow.h"
#include "libbead/model/identify.h"
#include "libbead/sim/rig_simulator.h"
#include "libbead/series/interpolate.h"

namespace bead::explain::twin {

// 24 s of PRBS on the extruder; the wheel commanded in steps so that its
// speed (and so the time from nozzle to laser) changes, which is what lets
// a position shift be told from a time shift.
inline sim::SimConfig Base(uint64_t seed) {
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

inline std::unique_ptr<Pipeline> RunPipeline(const sim::SimConfig& c) {
  auto p = std::make_unique<Pipeline>();
  p->sim = sim::Simulate(c);
  GeometryAndFlow m = MeasureFlow(p->sim.rig_file, p->sim.run.profiles, *p->sim.run.log);
  p->geometry = std::move(m.geometry);
  p->flow = std::move(m.flow);
  return p;
}

// The calibration run's model (with its operating point), identified once.
inline const model::IdentifiedModel& CalibrationModel() {
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

inline Outcome ExplainRun(const sim::SimConfig& c) {
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

inline const AddedEffect* Find(const ExplainReport& r, const std::string& name) {
  for (const auto& e : r.effects_added)
    if (e.name == name) return &e;
  return nullptr;
}

inline double Param(const AddedEffect& e, const std::string& name, double* ci) {
  for (const auto& p : e.parameters)
    if (p.name == name) {
      *ci = p.ci95;
      return p.value;
    }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

inline std::string Names(const ExplainReport& r) {
  std::string s = "added:";
  for (const auto& e : r.effects_added) {
    s += " " + e.name + " [";
    for (const auto& p : e.parameters)
      s += p.name + "=" + std::to_string(p.value) + "+-" + std::to_string(p.ci95) + " ";
    s += "rms " + std::to_string(e.rms_before) + " -> " + std::to_string(e.rms_after) + "]";
  }
  s += "; tried (round, name, BIC drop, held-out F):";
  for (const auto& c : r.candidates)
    s += " (" + std::to_string(c.round) + " " + c.name + " " + std::to_string(c.bic_drop) + " " +
         std::to_string(c.heldout_f) + " " + std::to_string(c.surrogate_f) + ")";
  return s;
}

// The same runs cut from a longer session (warm_start: the extruder and
// the wheel already running, in steady state at the command's base
// level), analysed with the calibration run's model.
inline sim::SimConfig Warm(uint64_t seed) {
  sim::SimConfig c = Base(seed);
  c.warm_start = true;
  c.extruder.command.start_s = 0.0;
  return c;
}

// A flow against the twin's true flow at its samples' extrusion times,
// once scaled by its best constant gain (the gain a model takes up): that
// gain, the RMS error there, and the flow's mean.
struct AgainstTruth {
  double gain, rms_at_gain, mean;
};
inline AgainstTruth Against(const FlowResult& f, const sim::FlowTruth& truth) {
  double qq = 0, qt = 0, sum = 0;
  std::vector<std::pair<double, double>> pairs;
  for (const auto& x : f.samples)
    if (x.valid && std::isfinite(x.t_s) && std::isfinite(x.flow_mm3_s)) {
      const double t = InterpolateLinear(truth.t_s, truth.flow_mm3_s, x.t_s);
      pairs.push_back({x.flow_mm3_s, t});
      qq += x.flow_mm3_s * x.flow_mm3_s, qt += x.flow_mm3_s * t, sum += x.flow_mm3_s;
    }
  const double k = qt / qq;
  double ss = 0;
  for (const auto& [q, t] : pairs) ss += (k * q - t) * (k * q - t);
  const auto n = static_cast<double>(pairs.size());
  return {k, std::sqrt(ss / n), sum / n};
}

}  // namespace bead::explain::twin
