// bead explain: close the loop - flow (or any measured series) against a
// model, residual diagnostics, the effects the model lacks added one at a
// time when they earn it, and the error before and after.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

#include "libbead/core/error.h"
#include "calibration/pin_offset.h"
#include "libbead/explain/corrected_flow.h"
#include "libbead/explain/explain_json.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/run_explain.h"
#include "libbead/explain/model_series.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/flow_csv.h"
#include "libbead/io/run_archive.h"
#include "libbead/series/process_on.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/model/identify.h"
#include "libbead/archive/measured_run.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "tools/commands.h"
#include "tools/subcommands.h"
#include "tools/csv_columns.h"
#include "tools/model_json.h"
#include "tools/occlusion_step.h"

namespace bead::tools {
namespace {

using nlohmann::json;

void PrintReport(const explain::ExplainReport& r, const std::string& unit) {
  std::printf(
      "\nthe model as given: fit %.2f %%, RMS error %.4g %s; residual %s (chi2 %.1f, 99 %% limit %.1f), %s the input\n",
      r.before.fit_pct, r.before.rms, unit.c_str(), r.before.whiteness.white ? "white" : "not white",
      r.before.whiteness.chi2, r.before.whiteness.chi2_limit,
      r.before.input.independent ? "independent of" : "correlated with");
  std::string refit;
  for (const auto& e : r.base_refit)
    for (const auto& p : e.parameters) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %s = %.4g +- %.2g", refit.empty() ? " " : ", ", e.name.c_str(),
                    p.name.c_str(), p.value, p.ci95);
      refit += buf;
    }
  std::printf("base model refitted with every candidate:%s\n", refit.c_str());
  if (r.base.misspecified)
    std::printf(
        "warning: the base model's dynamics are misspecified: a linear correction of them lowers the held-out "
        "RMS %.4g -> %.4g (F %.1f > %.1f); re-identify it (more poles or zeros, another delay). Effects are "
        "only added beyond that correction.\n",
        r.base.rms_before, r.base.rms_after, r.base.heldout_f, r.base.threshold);
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
  for (const auto& c : r.confounded)
    std::printf("confounded: %s and %s trade (correlation %+.3f): %s\n", c.first.c_str(), c.second.c_str(),
                c.correlation, c.note.c_str());
}

void PrintRun(const explain::RunExplanation& e, const Rig& rig, const std::string& path, const std::string& validate) {
  for (const auto& c : e.series.data.channels)
    std::printf("recorded channel: %s (%s), tried as a cause\n", c.name.c_str(),
                c.unit.empty() ? "no unit" : c.unit.c_str());
  if (!validate.empty()) std::printf("held-out data: %s\n", validate.c_str());
  std::printf("%s: %zu samples of flow in extrusion time\n", path.c_str(), e.series.data.size());
  PrintReport(e.report, "mm^3/s");
  const explain::OffsetFromRun& o = e.offset;
  if (!o.pinned)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: its 95 %% interval %.1f to %.1f counts reaches "
        "the searched range (lowest error at %.1f; the wheel's speed changes too little to tell a position "
        "error from a time error); rig file: %.1f counts\n",
        o.lo_counts, o.hi_counts, o.counts, rig.offset_counts);
  else
    std::printf(
        "encoder offset from the run: %.1f counts, 95 %% interval %.1f to %.1f (the residual's colour and the "
        "delay refitted at every offset accounted for); rig file: %.1f counts%s\n",
        o.counts, o.lo_counts, o.hi_counts, rig.offset_counts, o.excludes_rig ? " -- OUTSIDE the run's interval" : "");
  std::printf("profile time stamps against the log: %+.4f +- %.4f s (a sensor latency shows here)\n",
              e.series.timestamp_offset_s, e.series.timestamp_offset_ci95_s);
}

void PrintPins(const explain::OffsetComparison& c, const explain::OffsetFromRun& run, const std::string& path) {
  std::printf("pin scans (%s): %.1f +- %.1f counts; the run's offset differs by %+.1f counts\n", path.c_str(),
              c.pins_counts, c.pins_ci95_counts, c.difference);
  if (!c.run_pinned)
    std::printf("offset: the run does not pin it; the pins' %.1f +- %.1f counts stands alone\n", c.pins_counts,
                c.pins_ci95_counts);
  else if (c.agree)
    std::printf("offset, run and pins combined: %.1f +- %.1f counts (they agree within their intervals)\n",
                c.combined_counts, c.combined_ci95_counts);
  else
    std::printf(
        "offset: the run (%.1f +- %.1f) and the pins (%.1f +- %.1f) DISAGREE by %.1f counts, more than their "
        "intervals allow: a pin placed off the nozzle's centre, a slipped encoder, or an effect the run's "
        "model lacks; they are not combined\n",
        run.counts, run.ci95_counts, c.pins_counts, c.pins_ci95_counts, c.difference);
}

void PrintCorrected(const explain::CorrectedFlow& cf, const std::string& path) {
  std::string undone;
  for (const auto& u : cf.undone) undone += (undone.empty() ? "" : ", ") + u;
  if (cf.lowers_error) {
    std::printf(
        "corrected flow: %s undone (offset %.1f counts); held-out RMS against the model %.4g -> %.4g mm^3/s; "
        "total volume %.1f mm^3\nwrote %s\n",
        undone.c_str(), cf.offset_counts, cf.rms_before, cf.rms_after, cf.flow.total_volume_mm3, path.c_str());
    return;
  }
  std::printf("corrected flow NOT written (%s): %s%s%s\n", path.c_str(), cf.why_not.c_str(),
              undone.empty() ? "" : "; tried: ", undone.c_str());
  if (!undone.empty())
    std::printf("  held-out RMS against the model %.4g -> %.4g mm^3/s\n", cf.rms_before, cf.rms_after);
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
    std::string rig, data, model, out, input, output, time, input_file, input_time, validate, validate_input_file, pins,
        flow_out, structure = "tf", occlusion = "pooled";
    int poles = 2, zeros = 2;
    double max_delay_s = 1.0, alpha = 0.01;
    int max_effects = 5;
    bool keep_off = false, no_channels = false;
    std::vector<std::string> channels;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("explain", Summary("explain"));
  cmd->footer(
      "Run mode:  bead explain --rig RIG.yaml RUN.h5 [--model model.json] [--validate OTHER.h5] [--pins PINS.h5]\n"
      "           [--flow-out corrected.csv] -o explain.json\n"
      "  measures the run, computes the flow Q = v A (bead flow), takes the model of flow from screw\n"
      "  RPM (--model, from `bead identify -o`; else identified on this run, operating point and initial\n"
      "  state estimated), then adds, one at a time, the effects that lower the BIC and pass a held-out\n"
      "  test: encoder offset, changing delay, once/twice per revolution of the wheel or screw, cooling\n"
      "  shrink, height dependence, drift, build-up, level-dependent gain and lag. The base model's gain,\n"
      "  operating point and delay are refitted with and without every candidate, and a candidate must\n"
      "  also beat a linear correction of the base model's dynamics, so a wrong base model cannot buy an\n"
      "  effect (the report says when the base model is misspecified). With --validate another run of\n"
      "  the same rig is the held-out data. Reports the encoder offset the run itself implies, from a\n"
      "  profile of the fit over the offset with its 95 % interval, beside the rig file's and the pin\n"
      "  scans' (--pins); the profile time stamps against the log (a sensor latency); and with\n"
      "  --flow-out the flow CSV with the kept effects that act on the measurement undone (offset\n"
      "  re-aligned, a wheel's once-per-revolution speed error removed, shrinkage added back).\n"
      "CSV mode:  bead explain DATA.csv --input COL --output COL [--time COL] [--validate OTHER.csv]\n"
      "  the same loop on any measured series (uneven sampling, gaps, a start mid-process; stretches where\n"
      "  the output sits at zero while the input does not are reported as process off and left out);\n"
      "  --input-file/--input-time take the input from its own file and clock, held at the output's times.\n"
      ".mat mode: DATA.mat (MATLAB v4/v5/v7.3) with --input, --output and --time naming vector variables;\n"
      "  --input-time VAR --output-time VAR when the two were sampled on their own clocks (the input held\n"
      "  at the output's times, as a power source's state is). Objects, cells, structs and a function\n"
      "  workspace in the file are skipped and listed.\n"
      "Out: a table (effect, parameters, fit % and RMS before and after), what stays unexplained, and\n"
      "  -o explain.json with effects_added, base_refit, base_model, unexplained, offset_from_run_counts,\n"
      "  offset_from_run_ci95_counts, offset_profile, rig_offset_counts, diagnostics and spectrum.\n"
      "Examples:\n"
      "  bead explain --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o explain.json\n"
      "  bead explain width.csv --time t --output w --input-file wfs.csv --input-time t --input wfs -o explain.json\n"
      "  bead explain bead1.mat --input wfs --input-time powersource_state_time --output width_f_array \\\n"
      "       --output-time width_f_time -o explain.json");
  cmd->add_option("data", args->data, "RUN.h5 (with --rig), DATA.csv or DATA.mat")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--rig", args->rig, "Rig file (YAML): run mode")->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model, "Model JSON (bead identify -o); else identified on the data")
      ->check(CLI::ExistingFile);
  cmd->add_option("--input", args->input, "CSV mode: input column");
  cmd->add_option("--output", args->output, "CSV mode: output column");
  cmd->add_option("--time,--output-time", args->time,
                  "CSV/.mat mode: time column or variable (s) of the output (and the input)");
  cmd->add_option("--input-file", args->input_file, "CSV mode: the input's own CSV (its own clock)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--input-time", args->input_time,
                  "CSV/.mat mode: the input's own time column or variable (in --input-file, else in DATA)");
  cmd->add_flag("--keep-off", args->keep_off, "CSV mode: explain the stretches where the process was off too");
  cmd->add_option("--validate", args->validate, "Another run (same rig, or same columns): the held-out data")
      ->check(CLI::ExistingFile);
  cmd->add_option("--validate-input-file", args->validate_input_file,
                  "CSV mode, with --input-file: the held-out run's own input CSV")
      ->check(CLI::ExistingFile);
  cmd->add_option("--pins", args->pins, "Run mode: pin scans of this rig, to compare the offsets")
      ->check(CLI::ExistingFile);
  cmd->add_option("--flow-out", args->flow_out,
                  "Run mode: the corrected flow CSV to write (atomically), only if the correction lowers the "
                  "held-out error");
  cmd->add_option("--channels", args->channels,
                  "The recorded channels to try as causes: run mode /log/<name> (default: every one); CSV/.mat "
                  "mode columns or variables of DATA on its --time clock (default: none)")
      ->delimiter(',');
  cmd->add_flag("--no-channels", args->no_channels, "Try no recorded channel");
  cmd->add_option("--poles", args->poles, "Identified model: poles")->capture_default_str()->check(CLI::Range(1, 6));
  cmd->add_option("--zeros", args->zeros, "Identified model: zeros")->capture_default_str()->check(CLI::Range(0, 6));
  cmd->add_option("--structure", args->structure, "Identified model: tf, or P1D, P1DZ, P2D, P2DZ, P3D, P3DZ")
      ->capture_default_str();
  cmd->add_option("--max-delay-s", args->max_delay_s, "Identified model: largest delay searched")
      ->capture_default_str();
  cmd->add_option("--alpha", args->alpha, "Significance level of the held-out test")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.2));
  cmd->add_option("--max-effects", args->max_effects, "At most this many effects")->capture_default_str();
  cmd->add_option("-o,--out", args->out, "explain.json to write (atomically)")->required();
  AddOcclusionOption(cmd, args->occlusion);
  return [args]() {
    explain::ExplainOptions options;
    options.alpha = args->alpha;
    options.max_effects = args->max_effects;
    model::IdentifyOptions id;
    id.poles = args->poles;
    id.zeros = std::min(args->zeros, args->poles);
    ApplyStructure(args->structure, id);
    id.max_delay_s = args->max_delay_s;
    struct Model {
      model::TransferFunction tf;
      double offset = 0.0;
      std::string source;
    };
    auto model_for = [&](const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                         const std::vector<Segment>& segments, const std::string& where) {
      Model m;
      if (!args->model.empty()) {
        const ModelFile f = ReadModelFile(args->model);
        m.tf = f.tf;
        m.offset = f.offset;
        m.source = args->model;
        return m;
      }
      const model::IdentifiedModel im = model::IdentifyTransferFunction(t, u, y, id, segments);
      if (!im.ok) throw Error(Located(where, "", "no model could be identified: " + im.reason));
      m.tf = im.tf;
      m.offset = im.offset;
      m.source = "identified on " + where + " (" + std::to_string(id.poles) + " poles, " + std::to_string(id.zeros) +
                 " zeros, operating point and initial state estimated)";
      std::printf("model identified: fit %.2f %%, delay %.3f s\n", im.fit_percent, im.tf.delay_s);
      if (im.delay_profile.ambiguous) std::printf("warning: %s\n", im.delay_profile.note.c_str());
      return m;
    };

    if (!args->rig.empty()) {
      const Rig rig = ReadRig(args->rig);
      // A run measured: its flow in extrusion time (kept alive with the archive).
      struct Measured {
        MeasuredRun measured;
        FlowResult flow;
        std::vector<double> t, u, y;  // valid samples
      };
      WorkerPool pool;
      MeasureRunOptions measure_options;
      measure_options.occlusion = ParseOcclusionMode(args->occlusion);
      measure_options.estimate = occlusion::EstimateOcclusion;
      auto measure = [&](const std::string& path) {
        auto m = std::make_unique<Measured>();
        OpenedRun opened = OpenRun(path, pool);
        RequireMotion(opened.run, path, "explain");
        m->measured = MeasureWholeRun(std::move(opened), rig, pool, measure_options);
        const MeasuredRun& r = m->measured;
        if (const std::string line = OcclusionLine(r.summary); !line.empty()) std::printf("%s\n", line.c_str());
        m->flow = ComputeFlow(rig, r.run.profiles, r.geometry, *r.run.log, {}, r.corrected, r.sigma);
        for (const std::string& w : m->flow.warnings)
          std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), w.c_str());
        for (const auto& s : m->flow.samples)
          if (s.valid) m->t.push_back(s.t_s), m->u.push_back(s.screw_rpm), m->y.push_back(s.flow_mm3_s);
        if (m->t.size() < 50) throw Error(Located(path, "", "fewer than 50 profiles with a flow: nothing to explain"));
        return m;
      };
      const auto main_run = measure(args->data);
      const Model mdl = model_for(main_run->t, main_run->u, main_run->y, {}, args->data);
      std::unique_ptr<Measured> other;
      if (!args->validate.empty()) other = measure(args->validate);
      auto view = [](const Measured& m, const std::string& path) {
        return explain::MeasuredFlow{path,    &m.measured.run.profiles, &m.measured.geometry, &*m.measured.run.log,
                                     &m.flow, &m.measured.corrected,    &m.measured.sigma};
      };
      explain::RunExplainOptions run_options;
      run_options.explain = options;
      run_options.channels = args->channels;
      run_options.no_channels = args->no_channels;
      run_options.correct_flow = !args->flow_out.empty();
      const explain::MeasuredFlow main_view = view(*main_run, args->data);
      const explain::MeasuredFlow other_view = other ? view(*other, args->validate) : explain::MeasuredFlow{};
      std::printf("%s: explaining the flow in extrusion time...\n", args->data.c_str());
      const explain::RunExplanation e =
          explain::ExplainMeasuredRun(rig, main_view, other ? &other_view : nullptr, mdl.tf, mdl.offset, run_options);
      PrintRun(e, rig, args->data, args->validate);
      std::optional<explain::OffsetComparison> pins;
      if (!args->pins.empty()) {
        const calibration::OffsetCalibration cal = calibration::CalibrateOffset(rig, ReadPinScanArchive(args->pins));
        if (!cal.ok) throw Error(Located(args->pins, "", "cannot calibrate: " + cal.reason));
        pins = explain::CompareOffsets(e.offset, cal.offset_counts, cal.ci95_counts);
        PrintPins(*pins, e.offset, args->pins);
      }
      if (e.corrected) {
        if (e.corrected->lowers_error) WriteFlowCsv(args->flow_out, e.corrected->flow);
        PrintCorrected(*e.corrected, args->flow_out);
      }
      const json j = explain::RunJson(e, rig, mdl.tf, mdl.offset, mdl.source, pins, args->flow_out);
      Write(args->out, j);
      return 0;
    }

    if (args->input.empty() || args->output.empty())
      throw CLI::RequiredError("CSV mode needs --input and --output (run mode needs --rig)");
    if (!args->flow_out.empty() || !args->pins.empty())
      throw CLI::ValidationError("--flow-out and --pins", "are for run mode (--rig)");
    CheckValidationInput(args->input_file, args->validate, args->validate_input_file);
    auto read = [&](const std::string& path) {
      // The input's own clock: --input-time, else --time's name in --input-file.
      const std::string in_file = path == args->data ? args->input_file : args->validate_input_file;
      const std::string in_time = !args->input_time.empty() ? args->input_time : in_file.empty() ? "" : args->time;
      return ReadSeries({path, args->time, args->input, args->output, in_file, in_time});
    };
    auto stretches = [&](const Series& s, const std::string& path) {
      return SeriesStretches(s, path, args->keep_off, "explain");
    };
    const Series s = read(args->data);
    std::printf("%s: %zu rows (%d skipped as gaps%s%s)\n", args->data.c_str(), s.t.size(), s.skipped,
                s.skipped ? "; the first at " : "", s.first_skip.c_str());
    if (!s.note.empty()) std::printf("%s\n", s.note.c_str());
    const ProcessOn on = stretches(s, args->data);
    const Model mdl = model_for(s.t, s.u, s.y, on.segments, args->data);
    // Named columns of the data file as recorded channels, on its clock.
    auto with_channels = [&](explain::SeriesData d, const std::string& path) {
      if (args->channels.empty() || args->no_channels) return d;
      const ChannelColumns c = ReadChannelColumns(path, args->time, args->channels);
      for (std::size_t k = 0; k < args->channels.size(); ++k)
        d.channels.push_back({args->channels[k], "", c.t, c.values[k]});
      return d;
    };
    const explain::SeriesData data =
        with_channels(explain::ModelSeries(s.t, s.u, s.y, mdl.tf, mdl.offset, on.segments, args->output), args->data);
    std::optional<explain::SeriesData> other;
    if (!args->validate.empty()) {
      const Series v = read(args->validate);
      const ProcessOn von = stretches(v, args->validate);
      other = with_channels(explain::ModelSeries(v.t, v.u, v.y, mdl.tf, mdl.offset, von.segments, args->output),
                            args->validate);
      options.validation = &*other;
      std::printf("held-out data: %s (%zu rows)\n", args->validate.c_str(), v.t.size());
    }
    const explain::ExplainReport r = explain::Explain(data, options);
    PrintReport(r, args->output);
    json j = explain::ReportJson(r, mdl.tf, mdl.offset, mdl.source);
    j["mode"] = "csv";
    j["offset_from_run_counts"] = nullptr;  // no wheel in a plain series
    j["offset_from_run_ci95_counts"] = nullptr;
    j["rig_offset_counts"] = nullptr;
    json left = json::array();
    for (const auto& e : on.excluded)
      left.push_back({{"t_begin_s", e.t_begin_s}, {"t_end_s", e.t_end_s}, {"reason", e.reason}});
    j["excluded"] = left;
    Write(args->out, j);
    return 0;
  };
}

}  // namespace bead::tools
