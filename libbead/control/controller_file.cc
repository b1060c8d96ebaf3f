#include "libbead/control/controller_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "libbead/control/polynomial.h"
#include "libbead/io/atomic_file.h"

namespace bead::control {
Evaluated Evaluate(const model::TransferFunction& plant, const Design& d) {
  Evaluated e;
  e.design = d;
  e.margins = ComputeMargins(plant, d.pid);
  double scale = plant.delay_s;
  for (const auto& r : Roots(plant.den)) scale += 1.0 / std::max(std::abs(r.real()), 1e-12);
  e.duration_s = std::min(40.0 / std::max(d.stability_degree, 1e-12), 200.0 * std::max(scale, 1e-9));
  e.setpoint = SetpointStep(plant, d.pid, e.duration_s);
  e.load = LoadStep(plant, d.pid, e.duration_s);
  return e;
}

void WriteControllerFile(const std::string& path, const Evaluated& e, const model::TransferFunction& plant,
                         const std::string& model_source) {
  // Infinite figures (no phase crossing: an unbounded gain margin; never
  // settled) are written as YAML's .inf.
  YAML::Emitter y;
  y.SetDoublePrecision(9);
  y << YAML::BeginMap;
  y << YAML::Key << "format" << YAML::Value << "bead controller 1";
  y << YAML::Key << "method" << YAML::Value << e.design.method;
  if (!e.design.note.empty()) y << YAML::Key << "note" << YAML::Value << e.design.note;
  y << YAML::Key << "pid" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "kp" << YAML::Value << e.design.pid.kp;
  y << YAML::Key << "ki" << YAML::Value << e.design.pid.ki;
  y << YAML::Key << "kd" << YAML::Value << e.design.pid.kd;
  y << YAML::Key << "derivative_filter_s" << YAML::Value << e.design.pid.tf_s;
  y << YAML::Key << "form" << YAML::Value << "kp + ki / s + kd s / (1 + derivative_filter_s s)";
  y << YAML::EndMap;
  y << YAML::Key << "stability_degree" << YAML::Value << e.design.stability_degree;
  y << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "source" << YAML::Value << model_source;
  y << YAML::Key << "num" << YAML::Value << YAML::Flow << plant.num;
  y << YAML::Key << "den" << YAML::Value << YAML::Flow << plant.den;
  y << YAML::Key << "delay_s" << YAML::Value << plant.delay_s;
  y << YAML::EndMap;
  y << YAML::Key << "margins" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "gain_margin" << YAML::Value << e.margins.gain_margin;
  y << YAML::Key << "phase_margin_deg" << YAML::Value << e.margins.phase_margin_deg;
  y << YAML::Key << "crossover_rad_s" << YAML::Value << e.margins.crossover_rad_s;
  y << YAML::Key << "ms" << YAML::Value << e.margins.ms;
  y << YAML::EndMap;
  y << YAML::Key << "setpoint_step" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "overshoot_pct" << YAML::Value << e.setpoint.overshoot_pct;
  y << YAML::Key << "settling_s" << YAML::Value << e.setpoint.settling_s;
  y << YAML::Key << "settling_band" << YAML::Value << "+-5 % of the step";
  y << YAML::Key << "iae" << YAML::Value << e.setpoint.iae;
  y << YAML::EndMap;
  y << YAML::Key << "load_step" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "peak_deviation" << YAML::Value << e.load.peak_deviation;
  y << YAML::Key << "settling_s" << YAML::Value << e.load.settling_s;
  y << YAML::Key << "settling_band" << YAML::Value << "+-5 % of the model's gain";
  y << YAML::Key << "iae" << YAML::Value << e.load.iae;
  y << YAML::EndMap;
  y << YAML::Key << "simulated_s" << YAML::Value << e.duration_s;
  y << YAML::EndMap;
  AtomicFile out(path);
  out.stream() << y.c_str() << "\n";
  out.Commit();
}

}  // namespace bead::control
