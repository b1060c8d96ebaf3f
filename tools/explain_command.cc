// bead explain: close the loop - flow (or any measured series) against a
// model, residual diagnostics, the effects the model lacks added one at a
// time when they earn it, and the error before and after.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/model_series.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/model/identify.h"
#include "libbead/profile/measure_block.h"
#include "tools/commands.h"
#include "tools/csv_columns.h"
#include "tools/model_json.h"
#include "tools/load_profiles.h"
#include "tools/occlusion_step.h"

namespace bead::tools {
namespace {

using nlohmann::json;

json ToJson(const explain::Whiteness& w) {
  return {{"lags", w.lags}, {"acf", w.acf}, {"bound", w.bound}, {"outside", w.outside},
          {"chi2", w.chi2}, {"chi2_limit_99", w.chi2_limit}, {"white", w.white}};
}
json ToJson(const explain::InputCorrelation& x) {
  return {{"lags", x.lags}, {"ccf", x.ccf}, {"bound", x.bound}, {"outside", x.outside}, {"independent", x.independent}};
}
json ToJson(const explain::Spectrum& s) {
  json peaks = json::array();
  for (const auto& p : s.peaks)
    peaks.push_back({{"frequency_hz", p.frequency_hz}, {"power", p.power}, {"false_alarm", p.false_alarm}});
  return {{"frequency_hz", s.frequency_hz}, {"power", s.power}, {"peaks", peaks}};
}
json Finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json ReportJson(const explain::ExplainReport& r, const model::TransferFunction& tf, const std::string& model_source) {
  json effects = json::array();
  for (const auto& e : r.effects_added) {
    json params = json::object();
    for (const auto& p : e.parameters) params[p.name] = {{"value", p.value}, {"ci95", Finite(p.ci95)}};
    effects.push_back({{"name", e.name},
                       {"description", e.description},
                       {"tracks", e.tracks},
                       {"parameters", params},
                       {"fit_before_pct", e.fit_before_pct},
                       {"fit_after_pct", e.fit_after_pct},
                       {"rms_before", e.rms_before},
                       {"rms_after", e.rms_after},
                       {"bic_drop", e.bic_drop},
                       {"heldout_f", e.heldout_f}});
  }
  json unexplained = json::array();
  for (const auto& u : r.unexplained)
    unexplained.push_back({{"what", u.what},
                           {"tracks", u.tracks},
                           {"frequency_hz", u.frequency_hz},
                           {"power", u.power},
                           {"false_alarm", u.false_alarm}});
  json candidates = json::array();
  for (const auto& c : r.candidates)
    candidates.push_back({{"round", c.round}, {"name", c.name}, {"bic_drop", c.bic_drop}, {"heldout_f", c.heldout_f},
                          {"surrogate_f", Finite(c.surrogate_f)}, {"accepted", c.accepted}});
  return {{"model", {{"num", tf.num}, {"den", tf.den}, {"delay_s", tf.delay_s}, {"source", model_source}}},
          {"fit_before_pct", r.before.fit_pct},
          {"fit_after_pct", r.after.fit_pct},
          {"rms_before", r.before.rms},
          {"rms_after", r.after.rms},
          {"effects_added", effects},
          {"unexplained", unexplained},
          {"diagnostics",
           {{"whiteness_before", ToJson(r.before.whiteness)},
            {"whiteness_after", ToJson(r.after.whiteness)},
            {"input_correlation_before", ToJson(r.before.input)},
            {"input_correlation_after", ToJson(r.after.input)},
            {"candidates", candidates}}},
          {"spectrum", {{"before", ToJson(r.before.spectrum)}, {"after", ToJson(r.after.spectrum)}}}};
}

void PrintReport(const explain::ExplainReport& r, const std::string& unit) {
  std::printf("\nbefore: fit %.2f %%, RMS error %.4g %s; residual %s (chi2 %.1f, 99 %% limit %.1f), %s the input\n",
              r.before.fit_pct, r.before.rms, unit.c_str(), r.before.whiteness.white ? "white" : "not white",
              r.before.whiteness.chi2, r.before.whiteness.chi2_limit,
              r.before.input.independent ? "independent of" : "correlated with");
  std::printf("\n%-32s %-44s %9s %9s %11s %11s\n", "effect", "parameters (95 % interval)", "fit_bef_%", "fit_aft_%",
              "rms_before", "rms_after");
  if (r.effects_added.empty()) std::printf("%-32s\n", "(none added)");
  for (const auto& e : r.effects_added) {
    std::string params;
    for (const auto& p : e.parameters) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s=%.4g+-%.2g", params.empty() ? "" : ", ", p.name.c_str(), p.value, p.ci95);
      params += buf;
    }
    std::printf("%-32s %-44s %9.2f %9.2f %11.4g %11.4g\n", e.name.c_str(), params.c_str(), e.fit_before_pct,
                e.fit_after_pct, e.rms_before, e.rms_after);
  }
  std::printf("\nafter: fit %.2f %%, RMS error %.4g %s; residual %s (chi2 %.1f)\n", r.after.fit_pct, r.after.rms,
              unit.c_str(), r.after.whiteness.white ? "white" : "not white", r.after.whiteness.chi2);
  for (const auto& u : r.unexplained)
    std::printf("unexplained: %s, tracks %s (power %.1f, false alarm %.2g)\n", u.what.c_str(), u.tracks.c_str(),
                u.power, u.false_alarm);
}

void Write(const std::string& path, const json& j) {
  AtomicFile file(path);
  file.stream() << j.dump(2) << "\n";
  file.Commit();
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace

Run AddExplain(CLI::App& app) {
  struct Args {
    std::string rig, data, model, out, input, output, time, validate, occlusion = "pooled";
    int poles = 2, zeros = 2;
    double max_delay_s = 1.0, alpha = 0.01;
    int max_effects = 5;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("explain", "Find what the model lacks: residual diagnostics and effects added");
  cmd->footer(
      "Run mode:  bead explain --rig RIG.yaml RUN.h5 [--model model.json] [--validate OTHER.h5] -o explain.json\n"
      "  measures the run, computes the flow Q = v A (bead flow), takes the model of flow from screw\n"
      "  RPM (--model, from `bead identify -o`; else identified on this run), then adds, one at a time,\n"
      "  the effects that lower the BIC and pass a held-out test: encoder offset, time shift, changing\n"
      "  delay, once/twice per revolution of the wheel or screw, cooling shrink, height dependence,\n"
      "  drift, level-dependent gain and lag (and scale, bias with --model); with --validate another run\n"
      "  of the same rig is the held-out data. Reports the encoder offset the run\n"
      "  itself implies, with its 95 % interval, beside the rig file's; and the profile time stamps\n"
      "  against the log (a sensor latency).\n"
      "CSV mode:  bead explain DATA.csv --input COL --output COL [--time COL] [--validate OTHER.csv]\n"
      "  the same loop on any measured series (uneven sampling, gaps where the process was off), with\n"
      "  drift, saturating build-up, level-dependent gain and lag (a time constant changing with level),\n"
      "  time shift and changing delay; --validate\n"
      "  makes another run the held-out data (an effect must improve it).\n"
      "Out: a table (effect, parameters, fit % and RMS before and after), what stays unexplained, and\n"
      "  -o explain.json with effects_added, unexplained, offset_from_run_counts,\n"
      "  offset_from_run_ci95_counts, rig_offset_counts, diagnostics and spectrum.\n"
      "Examples:\n"
      "  bead explain --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o explain.json\n"
      "  bead explain weld.csv --time t_s --input wire_feed --output width_mm -o explain.json");
  cmd->add_option("data", args->data, "RUN.h5 (with --rig) or DATA.csv")->required()->check(CLI::ExistingFile);
  cmd->add_option("--rig", args->rig, "Rig file (YAML): run mode")->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model, "Model JSON (bead identify -o); else identified on the data")
      ->check(CLI::ExistingFile);
  cmd->add_option("--input", args->input, "CSV mode: input column");
  cmd->add_option("--output", args->output, "CSV mode: output column");
  cmd->add_option("--time", args->time, "CSV mode: time column (s)");
  cmd->add_option("--validate", args->validate, "Another run (same rig, or same columns): the held-out data")
      ->check(CLI::ExistingFile);
  cmd->add_option("--poles", args->poles, "Identified model: poles")->capture_default_str()->check(CLI::Range(1, 6));
  cmd->add_option("--zeros", args->zeros, "Identified model: zeros")->capture_default_str()->check(CLI::Range(0, 6));
  cmd->add_option("--max-delay-s", args->max_delay_s, "Identified model: largest delay searched")->capture_default_str();
  cmd->add_option("--alpha", args->alpha, "Significance level of the held-out test")->capture_default_str()
      ->check(CLI::Range(1e-6, 0.2));
  cmd->add_option("--max-effects", args->max_effects, "At most this many effects")->capture_default_str();
  cmd->add_option("-o,--out", args->out, "explain.json to write (atomically)")->required();
  AddOcclusionOption(cmd, args->occlusion);
  return [args]() {
    explain::ExplainOptions options;
    options.alpha = args->alpha;
    options.max_effects = args->max_effects;
    options.catalogue.model_given = !args->model.empty();
    model::IdentifyOptions id;
    id.poles = args->poles;
    id.zeros = std::min(args->zeros, args->poles);
    id.max_delay_s = args->max_delay_s;
    auto model_for = [&](const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                         const std::string& where, std::string& source) {
      if (!args->model.empty()) {
        source = args->model;
        return ReadModelFile(args->model).tf;
      }
      const model::IdentifiedModel m = model::IdentifyTransferFunction(t, u, y, id);
      if (!m.ok) throw Error(Located(where, "", "no model could be identified: " + m.reason));
      source = "identified on " + where + " (" + std::to_string(id.poles) + " poles, " + std::to_string(id.zeros) +
               " zeros)";
      std::printf("model identified: fit %.2f %%, delay %.3f s\n", m.fit_percent, m.tf.delay_s);
      return m.tf;
    };

    if (!args->rig.empty()) {
      const Rig rig = ReadRig(args->rig);
      // A run measured: its flow in extrusion time (kept alive with the archive).
      struct Measured {
        RunArchive run;
        std::vector<BeadGeometry> geometry;
        FlowResult flow;
        std::vector<double> t, u, y;  // valid samples
      };
      auto measure = [&](const std::string& path) {
        auto m = std::make_unique<Measured>();
        m->run = LoadRun(path);
        if (!m->run.log) throw Error(Located(path, "/log", "missing: explain needs the acquisition log"));
        const ProfileBlock& block = m->run.profiles;
        m->geometry = MeasureProfiles(
            block.size(), [&](std::size_t i) { return block.view(i); }, rig.reference_left, rig.reference_right, {});
        const OcclusionColumns occ = RunOcclusion(args->occlusion, rig, block, m->geometry);
        m->flow = ComputeFlow(rig, block, m->geometry, *m->run.log, {}, occ.corrected, occ.sigma);
        for (const auto& s : m->flow.samples)
          if (s.valid) m->t.push_back(s.t_s), m->u.push_back(s.screw_rpm), m->y.push_back(s.flow_mm3_s);
        if (m->t.size() < 50) throw Error(Located(path, "", "fewer than 50 profiles with a flow: nothing to explain"));
        return m;
      };
      const auto main_run = measure(args->data);
      std::string source;
      const model::TransferFunction tf = model_for(main_run->t, main_run->u, main_run->y, args->data, source);
      auto series_of = [&](const Measured& m) {
        return explain::MakeRunSeries(rig, m.run.profiles, m.geometry, *m.run.log, m.flow, tf);
      };
      const explain::RunSeries series = series_of(*main_run);
      std::optional<explain::RunSeries> other;
      if (!args->validate.empty()) {
        other = series_of(*measure(args->validate));
        options.validation = &other->data;
        std::printf("held-out data: %s (%zu samples)\n", args->validate.c_str(), other->data.size());
      }
      options.catalogue.has_wheel = true;
      options.catalogue.position_range_counts = rig.encoder.counts_per_rev / 20.0;
      std::printf("%s: %zu samples of flow in extrusion time; explaining...\n", args->data.c_str(), series.data.size());
      const explain::ExplainReport r = explain::Explain(series.data, options);
      PrintReport(r, "mm^3/s");
      const double offset = rig.offset_counts + r.position_shift_counts;
      std::printf("encoder offset from the run: %.1f +- %.1f counts (95 %%); rig file: %.1f counts\n", offset,
                  r.position_shift_ci95_counts, rig.offset_counts);
      std::printf("profile time stamps against the log: %+.4f +- %.4f s (a sensor latency shows here)\n",
                  series.timestamp_offset_s, series.timestamp_offset_ci95_s);
      json j = ReportJson(r, tf, source);
      j["mode"] = "run";
      j["offset_from_run_counts"] = offset;
      j["offset_from_run_ci95_counts"] = Finite(r.position_shift_ci95_counts);
      j["rig_offset_counts"] = rig.offset_counts;
      j["diagnostics"]["timestamp_offset_s"] = series.timestamp_offset_s;
      j["diagnostics"]["timestamp_offset_ci95_s"] = series.timestamp_offset_ci95_s;
      Write(args->out, j);
      return 0;
    }

    if (args->input.empty() || args->output.empty())
      throw CLI::RequiredError("CSV mode needs --input and --output (run mode needs --rig)");
    const Series s = ReadColumns(args->data, args->time, args->input, args->output);
    std::printf("%s: %zu rows (%d skipped as gaps)\n", args->data.c_str(), s.t.size(), s.skipped);
    std::string source;
    const model::TransferFunction tf = model_for(s.t, s.u, s.y, args->data, source);
    const explain::SeriesData data = explain::ModelSeries(s.t, s.u, s.y, tf, args->output);
    std::optional<explain::SeriesData> other;
    if (!args->validate.empty()) {
      const Series v = ReadColumns(args->validate, args->time, args->input, args->output);
      other = explain::ModelSeries(v.t, v.u, v.y, tf, args->output);
      options.validation = &*other;
      std::printf("held-out data: %s (%zu rows)\n", args->validate.c_str(), v.t.size());
    }
    const explain::ExplainReport r = explain::Explain(data, options);
    PrintReport(r, args->output);
    json j = ReportJson(r, tf, source);
    j["mode"] = "csv";
    j["offset_from_run_counts"] = nullptr;  // no wheel in a plain series
    j["offset_from_run_ci95_counts"] = nullptr;
    j["rig_offset_counts"] = nullptr;
    Write(args->out, j);
    return 0;
  };
}

}  // namespace bead::tools
