#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/model/degenerate_fit.h"
#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"
#include "tools/commands.h"
#include "tools/subcommands.h"
#include "tools/tty_progress.h"
#include "libbead/io/series_columns.h"
#include "tools/series_stretches.h"
#include "libbead/model/identify_multi.h"
#include "libbead/model/model_file.h"
#include "tools/model_print.h"

namespace bead::tools {

namespace {

// A per-input list (--poles 2,1): one value for every input, or one each.
template <class T>
T PerInput(const std::vector<T>& list, std::size_t i, std::size_t inputs, const char* option) {
  if (list.size() == 1) return list[0];
  if (list.size() == inputs) return list[i];
  throw Error(std::string(option) + " gives " + std::to_string(list.size()) +
              " values: give one for every input, or one for each");
}

std::vector<model::IdentifyOptions> OptionsPerInput(std::size_t inputs, const std::vector<int>& poles,
                                                    const std::vector<int>& zeros,
                                                    const std::vector<std::string>& structure,
                                                    const std::vector<std::string>& delay, double max_delay_s,
                                                    bool from_rest) {
  std::vector<model::IdentifyOptions> out;
  for (std::size_t i = 0; i < inputs; ++i) {
    model::IdentifyOptions o;
    o.poles = PerInput(poles, i, inputs, "--poles");
    o.zeros = PerInput(zeros, i, inputs, "--zeros");
    model::SetStructure(PerInput(structure, i, inputs, "--structure"), o);
    if (o.poles < 1 || o.poles > 6) throw Error("--poles must be 1 to 6");
    if (o.zeros < 0 || o.zeros > o.poles)
      throw Error("--zeros (" + std::to_string(o.zeros) + ") must be 0 to --poles (" + std::to_string(o.poles) + ")");
    o.max_delay_s = max_delay_s;
    o.estimate_offset = o.estimate_initial_state = !from_rest;
    const std::string d = PerInput(delay, i, inputs, "--delay");
    if (d != "auto") {
      try {
        o.delay_s = std::stod(d);
      } catch (const std::exception&) {
        throw Error("--delay must be 'auto' or a number of seconds, got '" + d + "'");
      }
      if (!(*o.delay_s >= 0)) throw Error("--delay must be >= 0 s");
    }
    out.push_back(o);
  }
  return out;
}

// `bead identify --input a,b`: a transfer function per input, backfitted.
int IdentifySeveral(const std::string& data, const std::string& time, const std::vector<std::string>& inputs,
                    const std::string& output, const std::vector<model::IdentifyOptions>& o, bool keep_off,
                    const std::string& validate, const std::string& out) {
  const MultiSeries est = ReadMultiSeries(data, time, inputs, output);
  PrintFileNote(est.s.file_note);
  std::printf("%s: %zu rows where every input and the output are numbers\n", data.c_str(), est.s.t.size());
  const ProcessOn on = SeriesStretches(est.s, data, keep_off, "fit");
  const model::MultiInputModel m = model::IdentifyMultiInput(est.s.t, est.u, est.s.y, o, on.segments);
  if (!m.ok) throw Error(Located(data, "", "no model: " + m.reason));
  PrintMultiInputModel(m, o, inputs);
  std::printf("fit on estimation data: %.2f %%\n", m.fit_percent);
  double fit_val = NAN;
  if (!validate.empty()) {
    const MultiSeries val = ReadMultiSeries(validate, time, inputs, output);
    PrintFileNote(val.s.file_note);
    const ProcessOn von = SeriesStretches(val.s, validate, keep_off, "validate");
    std::vector<model::TransferFunction> tfs;
    for (const auto& part : m.inputs) tfs.push_back(part.tf);
    fit_val =
        model::FitPercent(val.s.y, model::PredictMultiInput(tfs, m.offset, val.s.t, val.u, val.s.y, von.segments));
    std::printf("fit on validation data (%s, initial states fitted): %.2f %%\n", validate.c_str(), fit_val);
  }
  std::printf("AIC %.6g  AICc %.6g  BIC %.6g  FPE %.6g  (%d parameters)\n", m.criteria.aic, m.criteria.aicc,
              m.criteria.bic, m.criteria.fpe, m.parameters);
  if (!out.empty()) {
    nlohmann::json j = model::MultiInputModelJson(m, o, inputs, output, est.s.t, on.segments, on.excluded);
    if (!validate.empty()) j["fit_validation_pct"] = fit_val;
    AtomicFile file(out);
    file.stream() << j.dump(2) << "\n";
    file.Commit();
    std::printf("wrote %s\n", out.c_str());
  }
  return 0;
}

// The order-selection table: each order fitted on the estimation data and
// scored on the validation run, or (without one) fitted on the first half
// and scored on the second.
void PrintOrderTable(const Series& est, const std::vector<Segment>& on, const Series* val,
                     const std::vector<Segment>& val_on, const model::IdentifyOptions& o) {
  Series a = est, b = est;
  std::vector<Segment> sa = on, sb = on;
  if (val) {
    b = *val;
    sb = val_on;
  } else {
    const std::size_t h = est.t.size() / 2;
    a = Series{};
    a.t.assign(est.t.begin(), est.t.begin() + h);
    a.u.assign(est.u.begin(), est.u.begin() + h);
    a.y.assign(est.y.begin(), est.y.begin() + h);
    b = Series{};
    b.t.assign(est.t.begin() + h, est.t.end());
    b.u.assign(est.u.begin() + h, est.u.end());
    b.y.assign(est.y.begin() + h, est.y.end());
    sa.clear();
    sb.clear();
    for (const Segment& s : on) {
      if (s.begin < h) sa.push_back({s.begin, std::min(s.end, h), s.process_starts});
      // A stretch cut at the half goes on mid-process in the second half.
      if (s.end > h) sb.push_back({std::max(s.begin, h) - h, s.end - h, s.begin >= h && s.process_starts});
    }
  }
  std::printf("\n%6s %6s %12s %12s %12s %10s\n", "poles", "zeros", "fit_est_%", "fit_val_%", "AICc", "delay_s");
  std::fflush(stdout);
  const auto tty = TtyProgress("order table:", "orders fitted");
  const auto progress = [&tty](int done, int total) {
    if (tty) tty(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
  };
  const auto rows = model::OrderTable(a.t, a.u, a.y, b.t, b.u, b.y, o, sa, sb, progress);
  for (const auto& r : rows)
    std::printf("%6d %6d %12.2f %12.2f %12.6g %10.4f\n", r.poles, r.zeros, r.fit_estimation, r.fit_validation, r.aicc,
                r.delay_s);
}

// The smaller structure's options, as the user would type them.
std::string StructureFlags(const model::IdentifyOptions& o) {
  if (o.real_poles) return "--structure P" + std::to_string(o.poles) + "D" + (o.zeros > 0 ? "Z" : "");
  return "--poles " + std::to_string(o.poles) + " --zeros " + std::to_string(o.zeros);
}

// A degenerate fit (`d`, FindDegeneracy's) said, with the smaller structure refitted beside it;
// the findings (and the smaller structure's fit) for the model file.
nlohmann::json SayDegeneracy(const model::IdentifiedModel& m, const model::IdentifyOptions& o, const Series& est,
                             const std::vector<Segment>& on, const model::Degeneracy& d) {
  nlohmann::json out = nlohmann::json::array();
  if (!d.any()) return out;
  for (const std::string& f : d.findings) {
    std::printf("WARNING: degenerate fit: %s\n", f.c_str());
    out.push_back(f);
  }
  model::IdentifyOptions smaller;
  if (!model::SmallerStructure(o, d, smaller)) return out;
  std::printf("  fitting the smaller structure (%s) ...\n", StructureFlags(smaller).c_str());
  std::fflush(stdout);
  const model::IdentifiedModel s = model::IdentifyTransferFunction(est.t, est.u, est.y, smaller, on);
  if (!s.ok) return out;
  char line[300];
  std::snprintf(line, sizeof line, "the smaller structure (%s) fits %.2f %% against this model's %.2f %%%s",
                StructureFlags(smaller).c_str(), s.fit_percent, m.fit_percent,
                s.fit_percent >= m.fit_percent - 0.5 ? ": as well; use it" : "");
  std::printf("  %s\n", line);
  out.push_back(line);
  return out;
}

// One input: the model, its fit (and on the validation run), the order
// table when asked, the model file.
int IdentifyOne(const SeriesNames& names, const model::IdentifyOptions& o, const std::string& validate, bool keep_off,
                bool orders, const std::string& out) {
  const std::string input = names.inputs[0];
  const Series est = ReadOneInputSeries(names, names.data);
  auto stretches = [&](const Series& s, const std::string& path) { return SeriesStretches(s, path, keep_off, "fit"); };
  const ProcessOn on = stretches(est, names.data);
  const model::IdentifiedModel m = model::IdentifyTransferFunction(est.t, est.u, est.y, o, on.segments);
  if (!m.ok) throw Error(Located(names.data, "", "no model: " + m.reason));
  std::optional<Series> val;
  std::optional<ProcessOn> val_on;
  if (!validate.empty()) {
    val = ReadOneInputSeries(names, validate);
    val_on = stretches(*val, validate);
  }
  PrintModel(m, o);
  std::printf("fit on estimation data: %.2f %%\n", m.fit_percent);
  const model::Degeneracy degeneracy = model::FindDegeneracy(m, est.t, est.u, est.y, on.segments);
  const nlohmann::json warnings = SayDegeneracy(m, o, est, on.segments, degeneracy);
  double fit_val = NAN;
  if (val) {
    fit_val = model::ValidateFitPercent(m.tf, m.offset, val->t, val->u, val->y, val_on->segments);
    std::printf("fit on validation data (%s, initial state fitted): %.2f %%\n", validate.c_str(), fit_val);
  }
  std::printf("AIC %.6g  AICc %.6g  BIC %.6g  FPE %.6g  (%d parameters)\n", m.criteria.aic, m.criteria.aicc,
              m.criteria.bic, m.criteria.fpe, m.parameters);
  if (orders)
    PrintOrderTable(est, on.segments, val ? &*val : nullptr, val ? val_on->segments : std::vector<Segment>{}, o);
  if (const std::string why = model::UnusableReason(degeneracy); !out.empty() && !why.empty())
    throw Error(Located(out, "", "not written: " + why + " (--max-delay-s, --structure, --poles, --zeros)"));
  if (!out.empty()) {
    nlohmann::json j = model::ModelJson(m, o, input, names.output, est.t, on.segments, on.excluded);
    if (val) j["fit_validation_pct"] = fit_val;
    if (!warnings.empty()) j["degenerate"] = warnings;
    AtomicFile file(out);
    file.stream() << j.dump(2) << "\n";
    file.Commit();
    std::printf("wrote %s\n", out.c_str());
  }
  return 0;
}

}  // namespace

Run AddIdentify(CLI::App& app) {
  struct Args {
    std::string data, output, time, input_file, input_time, validate, validate_input_file, out;
    std::vector<std::string> inputs, structure = {"tf"}, delay = {"auto"};
    std::vector<int> poles = {model::IdentifyOptions{}.poles}, zeros = {model::IdentifyOptions{}.zeros};
    double max_delay_s = 1.0;
    bool orders = false, from_rest = false, keep_off = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("identify", Summary("identify"));
  cmd->footer(
      "In:  any CSV with a header row; --input and --output name its columns, --time the time column\n"
      "     (seconds; without it, rows are unit-spaced; uneven sampling is fine). Rows with an empty\n"
      "     field are gaps. Or a MATLAB .mat file: the names are then vector variables (objects, cells and\n"
      "     structs in it are skipped and listed). The input may come from its own clock (--input-time,\n"
      "     in --input-file or the same .mat, --output-time the output's):\n"
      "     it is held at each output time. The record may start mid-process: the operating point (a\n"
      "     constant term) and each stretch's initial state are estimated, as MATLAB's tfest does with\n"
      "     InitialCondition 'estimate' (--from-rest: neither). Where the output sits at zero while the\n"
      "     input does not (the arc or extruder off), the process was off: reported and left out;\n"
      "     where the output then grows from zero the process started there, from rest.\n"
      "     The delay: a profile of the loss at every sample step up to --max-delay-s, its best basins\n"
      "     refined by output error; two basins the data cannot tell apart are reported.\n"
      "     Several inputs (--input a,b: columns on the data's own clock) get a transfer function each,\n"
      "     as tfest with several inputs, by backfitting; --poles, --zeros, --structure and --delay then\n"
      "     take one value for all or one per input (--poles 2,1).\n"
      "Out: the model (and its process form K, Tp, Tz, Td for real poles), its operating point, MATLAB-\n"
      "     style fit % on the data as given (and on --validate), AIC/AICc/BIC/FPE; with --orders the\n"
      "     thesis Table 3 (poles 1-3, zeros 0-2), validated on --validate or on the second half of\n"
      "     DATA; -o a JSON model file (written atomically) with the delay profile.\n"
      "Checked: a degenerate fit (a pole faster than the sample interval, a zero that all but cancels a\n"
      "     pole, a gain whose sign the data contradict) is said with WARNING, the smaller structure refitted\n"
      "     and its fit printed beside; the model file carries the findings as `degenerate`. A model whose\n"
      "     gain has the data's opposite sign is not written (exit 1). A delay at the end of the range\n"
      "     searched is said (raise --max-delay-s); an input that holds one value over every sample\n"
      "     fitted is refused (nothing there shows the gain).\n"
      "Examples:\n"
      "  bead identify flow.csv --time t_s --input screw_rpm --output flow_mm3_s --poles 2 --zeros 2 -o model.json\n"
      "  bead identify run.csv --time t_s --input screw_rpm,barrel_temp_c --output flow_mm3_s --poles 2,1 --zeros 1,0\n"
      "  bead identify width.csv --time t --output w --input-file wfs.csv --input-time t --input wfs --structure P1D");
  cmd->add_option("data", args->data, "Data CSV or .mat")->required()->check(CLI::ExistingFile);
  cmd->add_option("--input", args->inputs, "Input column (several: a,b)")->required()->delimiter(',');
  cmd->add_option("--output", args->output, "Output column")->required();
  cmd->add_option("--time,--output-time", args->time, "Time column or .mat variable (s) of the output (and the input)");
  cmd->add_option("--input-file", args->input_file, "The input's own CSV (its own clock)")->check(CLI::ExistingFile);
  cmd->add_option("--input-time", args->input_time,
                  "The input's own time column or variable (in --input-file, else in DATA)");
  cmd->add_option("--poles", args->poles, "Number of poles (1-6; per input: 2,1)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--zeros", args->zeros, "Number of zeros (<= poles; per input: 1,0)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--structure", args->structure, "tf, or a process model: P1D, P1DZ, P2D, P2DZ, P3D, P3DZ (per input)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--delay", args->delay, "Input delay: auto or seconds (per input)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--max-delay-s", args->max_delay_s, "Largest delay searched by --delay auto")->capture_default_str();
  cmd->add_flag("--from-rest", args->from_rest, "No operating point or initial state: the data start from rest at 0");
  cmd->add_flag("--keep-off", args->keep_off, "Fit the stretches where the process was off too");
  cmd->add_option("--validate", args->validate, "Validation CSV (same columns)")->check(CLI::ExistingFile);
  cmd->add_option("--validate-input-file", args->validate_input_file,
                  "With --input-file: the validation run's own input CSV")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--orders", args->orders, "Print the order-selection table");
  cmd->add_option("-o,--out", args->out, "Model JSON to write");
  return [args]() {
    if (!args->out.empty()) CheckWritable(args->out);
    const SeriesNames names{args->data,       args->time,       args->output,
                            args->input_file, args->input_time, args->validate_input_file,
                            args->inputs};
    CheckInputClocks(names, args->validate);
    const std::vector<model::IdentifyOptions> per_input =
        OptionsPerInput(args->inputs.size(), args->poles, args->zeros, args->structure, args->delay, args->max_delay_s,
                        args->from_rest);
    if (args->inputs.size() > 1) {
      if (args->orders) throw Error("--orders takes one input");
      return IdentifySeveral(args->data, args->time, args->inputs, args->output, per_input, args->keep_off,
                             args->validate, args->out);
    }
    return IdentifyOne(names, per_input[0], args->validate, args->keep_off, args->orders, args->out);
  };
}

}  // namespace bead::tools
