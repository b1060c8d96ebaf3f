#include "libbead/explain/explain_json.h"

#include <algorithm>
#include <cmath>

namespace bead::explain {
using nlohmann::json;

namespace {

json ToJson(const Whiteness& w) {
  return {{"lags", w.lags},       {"acf", w.acf},   {"bound", w.bound},
          {"outside", w.outside}, {"chi2", w.chi2}, {"chi2_limit_99", w.chi2_limit},
          {"white", w.white}};
}
json ToJson(const InputCorrelation& x) {
  return {{"lags", x.lags}, {"ccf", x.ccf}, {"bound", x.bound}, {"outside", x.outside}, {"independent", x.independent}};
}
json ToJson(const Spectrum& s) {
  json peaks = json::array();
  for (const auto& p : s.peaks)
    peaks.push_back({{"frequency_hz", p.frequency_hz}, {"power", p.power}, {"false_alarm", p.false_alarm}});
  return {{"frequency_hz", s.frequency_hz}, {"power", s.power}, {"peaks", peaks}};
}

json Parameters(const std::vector<FittedParameter>& ps) {
  json params = json::object();
  for (const auto& p : ps) params[p.name] = {{"value", p.value}, {"ci95", Finite(p.ci95)}};
  return params;
}

json Confounded(const ExplainReport& r) {
  json out = json::array();
  for (const auto& c : r.confounded)
    out.push_back({{"first", c.first}, {"second", c.second}, {"correlation", c.correlation}, {"note", c.note}});
  return out;
}

}  // namespace

json Finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json ReportJson(const ExplainReport& r, const model::TransferFunction& tf, double offset,
                const std::string& model_source, const std::vector<NamedModel>& more) {
  json more_inputs = json::array();
  for (const NamedModel& m : more)
    more_inputs.push_back({{"input", m.input}, {"num", m.tf.num}, {"den", m.tf.den}, {"delay_s", m.tf.delay_s}});
  json effects = json::array();
  for (const auto& e : r.effects_added)
    effects.push_back({{"name", e.name},
                       {"description", e.description},
                       {"tracks", e.tracks},
                       {"parameters", Parameters(e.parameters)},
                       {"fit_before_pct", e.fit_before_pct},
                       {"fit_after_pct", e.fit_after_pct},
                       {"rms_before", e.rms_before},
                       {"rms_after", e.rms_after},
                       {"bic_drop", e.bic_drop},
                       {"heldout_f", e.heldout_f}});
  json base = json::object();
  for (const auto& e : r.base_refit) base[e.name] = Parameters(e.parameters);
  json unexplained = json::array();
  for (const auto& u : r.unexplained)
    unexplained.push_back({{"what", u.what},
                           {"tracks", u.tracks},
                           {"frequency_hz", u.frequency_hz},
                           {"power", u.power},
                           {"false_alarm", u.false_alarm}});
  json candidates = json::array();
  for (const auto& c : r.candidates)
    candidates.push_back({{"round", c.round},
                          {"name", c.name},
                          {"bic_drop", c.bic_drop},
                          {"heldout_f", c.heldout_f},
                          {"surrogate_f", Finite(c.surrogate_f)},
                          {"guarded_f", Finite(c.guarded_f)},
                          {"accepted", c.accepted}});
  return {{"model",
           {{"num", tf.num},
            {"den", tf.den},
            {"delay_s", tf.delay_s},
            {"operating_point", {{"offset", offset}}},
            {"more_inputs", more_inputs},
            {"source", model_source}}},
          {"fit_before_pct", r.before.fit_pct},
          {"fit_after_pct", r.after.fit_pct},
          {"rms_before", r.before.rms},
          {"rms_after", r.after.rms},
          {"base_refit", base},
          {"base_model",
           {{"tested", r.base.tested},
            {"misspecified", r.base.misspecified},
            {"dynamics_correction_heldout_f", r.base.heldout_f},
            {"threshold_f", r.base.threshold},
            {"heldout_rms_before", r.base.rms_before},
            {"heldout_rms_with_correction", r.base.rms_after}}},
          {"effects_added", effects},
          {"confounded", Confounded(r)},
          {"unexplained", unexplained},
          {"diagnostics",
           {{"whiteness_before", ToJson(r.before.whiteness)},
            {"whiteness_after", ToJson(r.after.whiteness)},
            {"input_correlation_before", ToJson(r.before.input)},
            {"input_correlation_after", ToJson(r.after.input)},
            {"candidates", candidates}}},
          {"spectrum", {{"before", ToJson(r.before.spectrum)}, {"after", ToJson(r.after.spectrum)}}}};
}

json CompareJson(const SeriesData& d, const ExplainReport& r, std::size_t max_points) {
  const std::size_t n = d.size(),
                    step = std::max<std::size_t>(1, (n + max_points - 1) / std::max<std::size_t>(max_points, 1));
  json t = json::array(), y = json::array(), before = json::array(), after = json::array();
  auto model = [&](const Diagnosis& g, std::size_t i) {
    return i < g.residual.size() ? Finite(d.y[i] - g.residual[i]) : json(nullptr);
  };
  for (std::size_t i = 0; i < n; i += step) {
    t.push_back(d.t[i]);
    y.push_back(Finite(d.y[i]));
    before.push_back(model(r.before, i));
    after.push_back(model(r.after, i));
  }
  return {{"t_s", t}, {"measured", y}, {"model_before", before}, {"model_after", after}, {"unit", d.y_unit}};
}

json ReidentifiedJson(const ReidentifiedProfile& r) {
  return {{"offset_counts", r.counts},           {"sse", r.sse},
          {"best_counts", Finite(r.best)},       {"ci95_low_counts", Finite(r.lo)},
          {"ci95_high_counts", Finite(r.hi)},    {"low_at_search_edge", r.lo_at_edge},
          {"high_at_search_edge", r.hi_at_edge}, {"scattered_by_basins", r.scattered}};
}

json RunJson(const RunExplanation& e, const Rig& rig, const model::TransferFunction& tf, double offset,
             const std::string& model_source, const std::optional<OffsetComparison>& pins,
             const std::string& flow_out) {
  const ExplainReport& r = e.report;
  const ShiftProfile& sp = r.shift_profile;
  json j = ReportJson(r, tf, offset, model_source);
  j["mode"] = "run";
  j["compare"] = CompareJson(e.series.data, r);
  j["offset_from_run_counts"] = e.offset.counts;
  j["offset_from_run_ci95_counts"] = Finite(e.offset.ci95_counts);  // null: the run does not pin it
  j["offset_from_run_pinned"] = e.offset.pinned;
  j["offset_delay_correlation"] = Finite(e.offset.delay_correlation);
  j["offset_profile_threshold_q"] = sp.q;  // SSE_min + 3.84 q bounds the interval
  j["offset_profile"] = {{"offset_counts", json::array()},
                         {"sse", sp.sse},
                         {"ci95_low_counts", e.offset.lo_counts},
                         {"ci95_high_counts", e.offset.hi_counts},
                         {"low_at_search_edge", sp.lo_at_edge},
                         {"high_at_search_edge", sp.hi_at_edge},
                         {"inseparable_from_delay", sp.inseparable},
                         {"speed_delay_correlation", Finite(sp.speed_delay_correlation)},
                         {"steady_wheel", sp.steady_wheel},
                         {"speed_share_from_input", Finite(sp.speed_input_share)},
                         {"speed_follows_input", sp.speed_follows_input}};
  for (double g : sp.shift_counts) j["offset_profile"]["offset_counts"].push_back(e.aligned_at_counts + g);
  j["rig_offset_counts"] = rig.offset_counts;
  j["diagnostics"]["timestamp_offset_s"] = e.series.timestamp_offset_s;
  j["diagnostics"]["timestamp_offset_ci95_s"] = e.series.timestamp_offset_ci95_s;
  if (pins) {
    j["pin_offset_counts"] = pins->pins_counts;
    j["pin_offset_ci95_counts"] = pins->pins_ci95_counts;
    j["offsets_agree"] = pins->agree;
    j["combined_offset_counts"] = Finite(pins->combined_counts);
    j["combined_offset_ci95_counts"] = Finite(pins->combined_ci95_counts);
  }
  if (e.corrected) {
    const CorrectedFlow& cf = *e.corrected;
    j["corrected_flow"] = {{"path", flow_out},
                           {"undone", cf.undone},
                           {"offset_counts", cf.offset_counts},
                           {"heldout_rms_before", cf.rms_before},
                           {"heldout_rms_after", cf.rms_after},
                           {"written", cf.lowers_error}};
    if (cf.lowers_error)
      j["corrected_flow"]["total_volume_mm3"] = cf.flow.total_volume_mm3;
    else
      j["corrected_flow"]["why_not"] = cf.why_not;
  }
  return j;
}

}  // namespace bead::explain
