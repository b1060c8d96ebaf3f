// bead.identify, bead.tune and bead.simulate: the model, controller and
// twin calls of the `bead` commands of the same names.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "libbead/control/controller_file.h"
#include "libbead/control/loop_check.h"
#include "libbead/control/pid_tuning.h"
#include "libbead/core/error.h"
#include "libbead/model/degenerate_fit.h"
#include "libbead/model/identify.h"
#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_config.h"
#include "libbead/sim/sim_writer.h"
#include "python/numpy_owned.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bead::python {
namespace {

using Vector = InputVector;

py::dict Identify(const Vector& t, const Vector& u, const Vector& y, int poles, int zeros, const std::string& structure,
                  std::optional<double> delay_s, double max_delay_s) {
  const std::vector<double> tv = ToVector(t, "identify", "t"), uv = ToVector(u, "identify", "u"),
                            yv = ToVector(y, "identify", "y");
  if (tv.size() != uv.size() || tv.size() != yv.size()) throw Error("identify: t, u and y must have one length");
  model::IdentifyOptions o;
  o.poles = poles, o.zeros = zeros, o.delay_s = delay_s, o.max_delay_s = max_delay_s;
  model::SetStructure(structure, o);
  model::IdentifiedModel m;
  model::Degeneracy d;
  {
    py::gil_scoped_release free;
    m = model::IdentifyTransferFunction(tv, uv, yv, o);
    d = model::FindDegeneracy(m, tv, uv, yv);
  }
  if (!m.ok) throw Error("identify: no model: " + m.reason);
  // The command's rule: a model of the wrong sign is not handed on.
  if (const std::string why = model::UnusableReason(d); !why.empty()) throw Error("identify: refused: " + why);
  return py::dict("num"_a = m.tf.num, "den"_a = m.tf.den, "delay_s"_a = m.tf.delay_s, "offset"_a = m.offset,
                  "fit_percent"_a = m.fit_percent, "degenerate"_a = d.findings,
                  "prediction"_a = Owned(std::move(m.prediction), {static_cast<py::ssize_t>(tv.size())}));
}

py::dict Tune(const std::vector<double>& num, const std::vector<double>& den, double delay_s, const std::string& method,
              double filter, double max_ms, double min_gain_margin) {
  const model::TransferFunction g{num, den, delay_s};
  control::Design d;
  control::Evaluated e;
  control::LoopVerdict v;
  {
    py::gil_scoped_release free;
    d = control::DesignPid(g, method);
    control::FilterDerivative(g, d, filter);
    if (d.ok) {
      e = control::Evaluate(g, d);
      v = control::CheckLoop(g, e, {0.0, max_ms, min_gain_margin});
    }
  }
  if (!d.ok) throw Error(method + ": no controller: " + d.reason);
  return py::dict("ok"_a = v.ok, "reasons"_a = v.failures, "kp"_a = d.pid.kp, "ki"_a = d.pid.ki, "kd"_a = d.pid.kd,
                  "derivative_filter_s"_a = d.pid.tf_s, "stability_degree"_a = d.stability_degree,
                  "ms"_a = e.margins.ms, "gain_margin"_a = v.upper_gain_margin,
                  "phase_margin_deg"_a = e.margins.phase_margin_deg, "overshoot_pct"_a = e.setpoint.overshoot_pct,
                  "settling_s"_a = e.setpoint.settling_s);
}

std::string Simulate(const std::string& config, const std::string& out_dir) {
  py::gil_scoped_release free;
  sim::WriteSimulatedRun(out_dir, sim::Simulate(sim::ReadSimConfig(config)));
  return out_dir;
}

}  // namespace

void AddModels(py::module_& m) {
  m.def("identify", &Identify, "t"_a, "u"_a, "y"_a, "poles"_a = 2, "zeros"_a = 1, "structure"_a = "tf",
        "delay_s"_a = py::none(), "max_delay_s"_a = 1.0,
        "Identify a transfer function from u to y (as `bead identify`): t in s, any sampling; the delay searched up "
        "to max_delay_s (s) unless delay_s fixes it; structure tf or P1D, P2D, ... Returns a dict: num, den "
        "(descending powers of s), delay_s (s), offset (y = offset + G u), fit_percent, degenerate (what the fit "
        "has more of than the data carry, in words), prediction [N].");
  m.def("tune", &Tune, "num"_a, "den"_a, "delay_s"_a = 0.0, "method"_a = "max-stability", "filter"_a = 0.0,
        "max_ms"_a = 2.0, "min_gain_margin"_a = 1.5,
        "A PID for a model (as `bead tune`): method max-stability, simc, imc, zn or cohen-coon; filter N sets the "
        "derivative filter Tf = kd / (N kp). Returns a dict: kp, ki, kd, derivative_filter_s (s), "
        "stability_degree (J, 1/s), ms, gain_margin, phase_margin_deg, overshoot_pct, settling_s (s), and ok with "
        "the reasons a loop fails (unstable, ill-posed, Ms or gain margin beyond max_ms, min_gain_margin).");
  m.def("simulate", &Simulate, "config"_a, "out_dir"_a,
        "Run the rig's digital twin (as `bead simulate CONFIG -o OUT_DIR`): writes run.h5, pins.h5, rig.yaml and "
        "truth.h5 into out_dir; returns out_dir.");
}

}  // namespace bead::python
