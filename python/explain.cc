// bead.explain: the explain loop on a measured series (as `bead explain
// DATA.csv --input U --output Y`), its report as a dict (explain.json's
// layout, docs/explain.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/explain/base_model.h"
#include "libbead/explain/explain_json.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/model_series.h"
#include "libbead/model/model_file.h"
#include "python/numpy_owned.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bead::python {
namespace {

using Vector = InputVector;

// The report as JSON text (the GIL released while the loop runs).
std::string ExplainText(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                        const std::string& model_path, const model::IdentifyOptions& id, double alpha, int max_effects,
                        const std::string& output) {
  py::gil_scoped_release free;
  const explain::BaseModel m = model_path.empty() ? explain::IdentifyBaseModel(t, {u}, y, {}, id, "the arrays")
                                                  : explain::BaseModelFromFile(model_path, 1);
  const explain::SeriesData d = explain::ModelSeries(t, u, y, m.tfs[0], m.offset, {}, output);
  explain::ExplainOptions o;
  o.alpha = alpha;
  o.max_effects = max_effects;
  const explain::ExplainReport r = explain::Explain(d, o);
  nlohmann::json j = explain::ReportJson(r, m.tfs[0], m.offset, m.source);
  j["mode"] = "python";
  j["compare"] = explain::CompareJson(d, r);
  return j.dump();
}

py::object Explain(const Vector& t, const Vector& u, const Vector& y, const std::string& model, int poles, int zeros,
                   double max_delay_s, double alpha, int max_effects, const std::string& output) {
  const std::vector<double> tv = ToVector(t, "explain", "t"), uv = ToVector(u, "explain", "u"),
                            yv = ToVector(y, "explain", "y");
  if (tv.size() != uv.size() || tv.size() != yv.size()) throw Error("explain: t, u and y must have one length");
  if (tv.size() < 50) throw Error("explain: fewer than 50 samples: nothing to explain");
  model::IdentifyOptions id;
  id.poles = poles, id.zeros = std::min(zeros, poles), id.max_delay_s = max_delay_s;
  const std::string text = ExplainText(tv, uv, yv, model, id, alpha, max_effects, output);
  return py::module_::import("json").attr("loads")(text);
}

}  // namespace

void AddExplain(py::module_& m) {
  const model::IdentifyOptions order;  // the one default order (model/identify.h)
  m.def("explain", &Explain, "t"_a, "u"_a, "y"_a, "model"_a = "", "poles"_a = order.poles, "zeros"_a = order.zeros,
        "max_delay_s"_a = 1.0, "alpha"_a = 0.01, "max_effects"_a = 5, "output"_a = "y",
        "What a model of y from u lacks (as `bead explain DATA.csv --input u --output y`): t in s, any sampling; "
        "`output` names y (as --output: the parameters' names carry it); the base model read from `model` (a bead "
        "identify JSON) or identified (poles, zeros, the delay searched "
        "up to max_delay_s s); effects added while each passes its held-out test at level alpha. Returns explain."
        "json's report as a dict (docs/data-formats.md): model, effects_added (each with its parameters and "
        "intervals), fit_before_pct, fit_after_pct, diagnostics, spectrum, compare (t_s, measured, model_before, "
        "model_after, in y's unit).");
}

}  // namespace bead::python
