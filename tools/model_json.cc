#include "tools/model_json.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "libbead/core/error.h"

namespace bead::tools {
namespace {

using nlohmann::json;

json Finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string Polynomial(const std::vector<double>& c) {
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

}  // namespace

ModelFile ReadModelFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(Located(path, "", "cannot open the model file"));
  json j;
  try {
    in >> j;
  } catch (const json::exception& e) {
    throw Error(Located(path, "", std::string("not JSON: ") + e.what()));
  }
  ModelFile f;
  try {
    f.tf.num = j.at("num").get<std::vector<double>>();
    f.tf.den = j.at("den").get<std::vector<double>>();
    f.tf.delay_s = j.value("delay_s", 0.0);
    if (j.contains("operating_point")) {
      f.offset = j.at("operating_point").at("offset").get<double>();
      f.has_operating_point = true;
    }
  } catch (const json::exception& e) {
    throw Error(Located(path, "",
                        std::string("needs num, den (arrays of numbers), delay_s and optionally "
                                    "operating_point.offset (a number): ") +
                            e.what()));
  }
  try {
    f.tf.Validate();
  } catch (const Error& e) {
    throw Error(Located(path, "", e.what()));
  }
  if (!std::isfinite(f.offset)) throw Error(Located(path, "operating_point.offset", "not a finite number"));
  return f;
}

json ModelJson(const model::IdentifiedModel& m, const model::IdentifyOptions& o, const std::string& input,
               const std::string& output, const std::vector<double>& t, const std::vector<Segment>& segments,
               const std::vector<Exclusion>& excluded) {
  json basins = json::array();
  for (const auto& b : m.delay_profile.basins)
    basins.push_back(
        {{"delay_s", b.delay_s}, {"profile_loss", Finite(b.profile_loss)}, {"refined_loss", Finite(b.refined_loss)}});
  json loss = json::array();
  for (double l : m.delay_profile.loss) loss.push_back(Finite(l));
  json initial = json::array();
  for (std::size_t s = 0; s < m.initial_state.size() && s < segments.size(); ++s)
    initial.push_back({{"t_s", t[segments[s].begin]},
                       {"from", segments[s].process_starts ? "rest: the process started" : "estimated"},
                       {"free_response", m.initial_state[s]}});
  json left_out = json::array();
  for (const auto& e : excluded)
    left_out.push_back({{"t_begin_s", e.t_begin_s}, {"t_end_s", e.t_end_s}, {"reason", e.reason}});
  json j = {
      {"format", "bead model 2"},
      {"input", input},
      {"output", output},
      {"num", m.tf.num},
      {"den", m.tf.den},
      {"delay_s", m.tf.delay_s},
      {"poles", o.poles},
      {"zeros", o.zeros},
      {"structure", o.real_poles ? "process (real poles)" : "transfer function"},
      {"operating_point", {{"offset", m.offset}, {"input_level", m.input_level}, {"output_level", m.output_level}}},
      {"initial_state", initial},
      {"parameters", m.parameters},
      {"fit_estimation_pct", m.fit_percent},
      {"aic", m.criteria.aic},
      {"aicc", m.criteria.aicc},
      {"bic", m.criteria.bic},
      {"fpe", m.criteria.fpe},
      {"poles_real", m.poles_real},
      {"poles_imag", m.poles_imag},
      {"delay_profile",
       {{"delay_s", m.delay_profile.delay_s},
        {"loss", loss},
        {"basins", basins},
        {"ambiguous", m.delay_profile.ambiguous},
        {"note", m.delay_profile.note}}},
      {"excluded", left_out}};
  if (m.process.valid) {
    j["process"] = {
        {"K", m.process.K}, {"Tp_s", m.process.Tp_s}, {"Tz_s", Finite(m.process.Tz_s)}, {"Td_s", m.process.Td_s}};
  }
  return j;
}

void PrintModel(const model::IdentifiedModel& m, const model::IdentifyOptions& o) {
  std::printf("model: (%s) / (%s) * exp(-%.4g s)%s\n", Polynomial(m.tf.num).c_str(), Polynomial(m.tf.den).c_str(),
              m.tf.delay_s, o.delay_s ? " (delay fixed)" : "");
  std::printf("DC gain %.6g; poles:", m.tf.DcGain());
  for (std::size_t k = 0; k < m.poles_real.size(); ++k) std::printf(" %.4g%+.4gi", m.poles_real[k], m.poles_imag[k]);
  std::printf("\n");
  if (m.process.valid) {
    std::printf("process form: K %.5g, Tp", m.process.K);
    for (double tp : m.process.Tp_s) std::printf(" %.4g", tp);
    std::printf(" s, Tz %.4g s, Td %.4g s\n", m.process.Tz_s, m.process.Td_s);
  }
  if (o.estimate_offset)
    std::printf("operating point: input %.5g, output %.5g (y = %.5g + G(s) u)\n", m.input_level, m.output_level,
                m.offset);
  for (std::size_t k = 0; k < m.delay_profile.basins.size(); ++k)
    std::printf("delay basin %zu: %.4f s, loss %.5g%s\n", k + 1, m.delay_profile.basins[k].delay_s,
                m.delay_profile.basins[k].refined_loss, k == 0 ? " (chosen)" : "");
  if (m.delay_profile.ambiguous) std::printf("warning: %s\n", m.delay_profile.note.c_str());
}

}  // namespace bead::tools
