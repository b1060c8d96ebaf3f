#include "libbead/model/model_file.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "libbead/core/error.h"

namespace bead::model {
namespace {

using nlohmann::json;

json Finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

TransferFunction ReadTransferFunction(const json& j, const std::string& path, const std::string& where) {
  TransferFunction tf;
  auto numbers = [&](const char* key) {
    const std::string at = where.empty() ? key : where + "." + key;
    if (!j.contains(key)) throw Error(Located(path, at, "missing: a model needs num and den (arrays of numbers)"));
    try {
      return j.at(key).get<std::vector<double>>();
    } catch (const json::exception&) {
      throw Error(Located(path, at, "must be an array of numbers (descending powers of s)"));
    }
  };
  tf.num = numbers("num");
  tf.den = numbers("den");
  if (j.contains("delay_s") && !j["delay_s"].is_number())
    throw Error(Located(path, where.empty() ? "delay_s" : where + ".delay_s", "must be a number of seconds"));
  tf.delay_s = j.value("delay_s", 0.0);
  try {
    tf.Validate();
  } catch (const Error& e) {
    throw Error(Located(path, where, e.what()));
  }
  if (!std::isfinite(tf.delay_s) || tf.delay_s < 0) throw Error(Located(path, where, "delay_s must be >= 0"));
  return tf;
}

// One input's transfer function, its process form and delay profile.
json InputJson(const IdentifiedModel& m, const IdentifyOptions& o) {
  json basins = json::array();
  for (const auto& b : m.delay_profile.basins)
    basins.push_back(
        {{"delay_s", b.delay_s}, {"profile_loss", Finite(b.profile_loss)}, {"refined_loss", Finite(b.refined_loss)}});
  json loss = json::array();
  for (double l : m.delay_profile.loss) loss.push_back(Finite(l));
  json j = {{"num", m.tf.num},
            {"den", m.tf.den},
            {"delay_s", m.tf.delay_s},
            {"poles", o.poles},
            {"zeros", o.zeros},
            {"structure", o.real_poles ? "process (real poles)" : "transfer function"},
            {"poles_real", m.poles_real},
            {"poles_imag", m.poles_imag},
            {"delay_profile",
             {{"delay_s", m.delay_profile.delay_s},
              {"loss", loss},
              {"basins", basins},
              {"ambiguous", m.delay_profile.ambiguous},
              {"note", m.delay_profile.note},
              {"at_limit", m.delay_profile.at_limit}}}};
  if (m.process.valid)
    j["process"] = {
        {"K", m.process.K}, {"Tp_s", m.process.Tp_s}, {"Tz_s", Finite(m.process.Tz_s)}, {"Td_s", m.process.Td_s}};
  return j;
}

json InitialStates(const std::vector<std::vector<double>>& states, const std::vector<double>& t,
                   const std::vector<Segment>& segments) {
  json initial = json::array();
  for (std::size_t s = 0; s < states.size() && s < segments.size(); ++s)
    initial.push_back({{"t_s", t[segments[s].begin]},
                       {"from", segments[s].process_starts ? "rest: the process started" : "estimated"},
                       {"free_response", states[s]}});
  return initial;
}

json LeftOutJson(const std::vector<Exclusion>& excluded) {
  json left_out = json::array();
  for (const auto& e : excluded)
    left_out.push_back({{"t_begin_s", e.t_begin_s}, {"t_end_s", e.t_end_s}, {"reason", e.reason}});
  return left_out;
}

void AddCriteria(json& j, int parameters, double fit, const InformationCriteria& c) {
  j["parameters"] = parameters;
  j["fit_estimation_pct"] = fit;
  j["aic"] = c.aic;
  j["aicc"] = c.aicc;
  j["bic"] = c.bic;
  j["fpe"] = c.fpe;
}

}  // namespace

std::string PolynomialText(const std::vector<double>& c) {
  std::string out;
  const int n = static_cast<int>(c.size()) - 1;
  for (int k = 0; k <= n; ++k) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%s%.6g%s", k ? " + " : "", c[static_cast<std::size_t>(k)],
                  n - k == 0 ? "" : (n - k == 1 ? " s" : (" s^" + std::to_string(n - k)).c_str()));
    out += buf;
  }
  return out;
}

std::string JsonKind(const json& j) {
  if (!j.is_object()) return "";
  if (j.contains("effects_added") && j.contains("fit_before_pct")) return "explain";
  if (j.contains("inputs") || j.contains("num") || j.contains("den")) return "model";
  return "";
}

std::string DescribeJsonKind(const json& j) {
  const std::string kind = JsonKind(j);
  if (kind == "explain") return "an explain report (bead explain -o)";
  if (kind == "model") return "a model file (bead identify -o)";
  return "a JSON file of no kind libbead writes (neither a model file nor an explain report)";
}

ModelFile ReadModelFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(Located(path, "", "cannot open the model file"));
  json j;
  try {
    in >> j;
  } catch (const json::exception& e) {
    throw Error(Located(path, "", std::string("not JSON: ") + e.what()));
  }
  if (!j.is_object()) throw Error(Located(path, "", "not a model file (a JSON object with num and den)"));
  if (JsonKind(j) != "model")
    throw Error(Located(path, "", "is " + DescribeJsonKind(j) + ", not a model file (bead identify -o)"));
  ModelFile f;
  f.output = j.contains("output") && j["output"].is_string() ? j["output"].get<std::string>() : "";
  if (j.contains("inputs")) {  // version 3: several inputs
    if (!j["inputs"].is_array() || j["inputs"].empty())
      throw Error(Located(path, "inputs", "must be a non-empty array of transfer functions"));
    for (std::size_t i = 0; i < j["inputs"].size(); ++i) {
      const json& e = j["inputs"][i];
      const std::string where = "inputs[" + std::to_string(i) + "]";
      if (!e.is_object()) throw Error(Located(path, where, "must be an object with num, den and delay_s"));
      f.tfs.push_back(ReadTransferFunction(e, path, where));
      f.inputs.push_back(e.contains("input") && e["input"].is_string() ? e["input"].get<std::string>() : "");
    }
  } else {
    f.tfs.push_back(ReadTransferFunction(j, path, ""));
    f.inputs.push_back(j.contains("input") && j["input"].is_string() ? j["input"].get<std::string>() : "");
  }
  if (j.contains("operating_point")) {
    try {
      f.offset = j.at("operating_point").at("offset").get<double>();
    } catch (const json::exception& e) {
      throw Error(Located(path, "operating_point.offset", std::string("must be a number: ") + e.what()));
    }
    f.has_operating_point = true;
  }
  if (!std::isfinite(f.offset)) throw Error(Located(path, "operating_point.offset", "not a finite number"));
  return f;
}

json ModelJson(const IdentifiedModel& m, const IdentifyOptions& o, const std::string& input, const std::string& output,
               const std::vector<double>& t, const std::vector<Segment>& segments,
               const std::vector<Exclusion>& excluded) {
  json j = InputJson(m, o);
  j["format"] = "bead model 2";
  j["input"] = input;
  j["output"] = output;
  j["operating_point"] = {{"offset", m.offset}, {"input_level", m.input_level}, {"output_level", m.output_level}};
  j["initial_state"] = InitialStates(m.initial_state, t, segments);
  AddCriteria(j, m.parameters, m.fit_percent, m.criteria);
  j["excluded"] = LeftOutJson(excluded);
  return j;
}

json MultiInputModelJson(const MultiInputModel& m, const std::vector<IdentifyOptions>& o,
                         const std::vector<std::string>& inputs, const std::string& output,
                         const std::vector<double>& t, const std::vector<Segment>& segments,
                         const std::vector<Exclusion>& excluded) {
  json list = json::array();
  double output_level = m.offset;
  for (std::size_t i = 0; i < m.inputs.size(); ++i) {
    json e = InputJson(m.inputs[i], o[i]);
    e["input"] = inputs[i];
    e["input_level"] = m.inputs[i].input_level;
    e["initial_state"] = InitialStates(m.inputs[i].initial_state, t, segments);
    output_level += m.inputs[i].output_level;
    list.push_back(e);
  }
  json j = {{"format", "bead model 3"},
            {"output", output},
            {"inputs", list},
            {"operating_point", {{"offset", m.offset}, {"output_level", output_level}}},
            {"backfitting", {{"sweeps", m.sweeps}, {"converged", m.converged}}},
            {"max_input_correlation", m.max_input_correlation},
            {"note", m.note}};
  AddCriteria(j, m.parameters, m.fit_percent, m.criteria);
  j["excluded"] = LeftOutJson(excluded);
  return j;
}

}  // namespace bead::model
