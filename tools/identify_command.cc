#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"
#include "tools/commands.h"
#include "tools/subcommands.h"
#include "tools/csv_columns.h"
#include "tools/model_json.h"

namespace bead::tools {

// --structure: tf (any poles/zeros) or a procest-style process model.
void ApplyStructure(const std::string& structure, model::IdentifyOptions& o) {
  if (structure == "tf") return;
  struct Form {
    const char* name;
    int poles, zeros;
  };
  static const Form forms[] = {{"P1D", 1, 0},  {"P1DZ", 1, 1}, {"P2D", 2, 0},
                               {"P2DZ", 2, 1}, {"P3D", 3, 0},  {"P3DZ", 3, 1}};
  for (const Form& f : forms)
    if (structure == f.name) {
      o.poles = f.poles;
      o.zeros = f.zeros;
      o.real_poles = true;
      return;
    }
  throw Error("--structure must be tf, P1D, P1DZ, P2D, P2DZ, P3D or P3DZ, got '" + structure + "'");
}

Run AddIdentify(CLI::App& app) {
  struct Args {
    std::string data, input, output, time, input_file, input_time, delay = "auto", validate, validate_input_file, out,
                                                                   structure = "tf";
    int poles = 2, zeros = 1;
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
      "Out: the model (and its process form K, Tp, Tz, Td for real poles), its operating point, MATLAB-\n"
      "     style fit % on the data as given (and on --validate), AIC/AICc/BIC/FPE; with --orders the\n"
      "     thesis Table 3 (poles 1-3, zeros 0-2), validated on --validate or on the second half of\n"
      "     DATA; -o a JSON model file (written atomically) with the delay profile.\n"
      "Examples:\n"
      "  bead identify flow.csv --time t_s --input screw_rpm --output flow_mm3_s --poles 2 --zeros 2 -o model.json\n"
      "  bead identify width.csv --time t --output w --input-file wfs.csv --input-time t --input wfs --structure P1D");
  cmd->add_option("data", args->data, "Data CSV or .mat")->required()->check(CLI::ExistingFile);
  cmd->add_option("--input", args->input, "Input column")->required();
  cmd->add_option("--output", args->output, "Output column")->required();
  cmd->add_option("--time,--output-time", args->time, "Time column or .mat variable (s) of the output (and the input)");
  cmd->add_option("--input-file", args->input_file, "The input's own CSV (its own clock)")->check(CLI::ExistingFile);
  cmd->add_option("--input-time", args->input_time,
                  "The input's own time column or variable (in --input-file, else in DATA)");
  cmd->add_option("--poles", args->poles, "Number of poles")->capture_default_str()->check(CLI::Range(1, 6));
  cmd->add_option("--zeros", args->zeros, "Number of zeros (<= poles)")->capture_default_str()->check(CLI::Range(0, 6));
  cmd->add_option("--structure", args->structure, "tf, or a process model: P1D, P1DZ, P2D, P2DZ, P3D, P3DZ")
      ->capture_default_str();
  cmd->add_option("--delay", args->delay, "Input delay: auto or seconds")->capture_default_str();
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
    CheckValidationInput(args->input_file, args->validate, args->validate_input_file);
    auto read = [&](const std::string& path) {
      // The input's own clock: --input-time, else --time's name in --input-file.
      const std::string in_file = path == args->data ? args->input_file : args->validate_input_file;
      const std::string in_time = !args->input_time.empty() ? args->input_time : in_file.empty() ? "" : args->time;
      return ReadSeries({path, args->time, args->input, args->output, in_file, in_time});
    };
    const Series est = read(args->data);
    model::IdentifyOptions o;
    o.poles = args->poles;
    o.zeros = args->zeros;
    ApplyStructure(args->structure, o);
    if (o.zeros > o.poles) throw Error("--zeros (" + std::to_string(o.zeros) + ") must not exceed --poles");
    o.max_delay_s = args->max_delay_s;
    o.estimate_offset = o.estimate_initial_state = !args->from_rest;
    if (args->delay != "auto") {
      try {
        o.delay_s = std::stod(args->delay);
      } catch (const std::exception&) {
        throw Error("--delay must be 'auto' or a number of seconds, got '" + args->delay + "'");
      }
      if (!(*o.delay_s >= 0)) throw Error("--delay must be >= 0 s");
    }
    std::printf("%s: %zu rows (%d skipped as gaps%s%s)\n", args->data.c_str(), est.t.size(), est.skipped,
                est.skipped ? "; the first at " : "", est.first_skip.c_str());
    if (!est.note.empty()) std::printf("%s\n", est.note.c_str());
    auto stretches = [&](const Series& s, const std::string& path) {
      return SeriesStretches(s, path, args->keep_off, "fit");
    };
    const ProcessOn on = stretches(est, args->data);
    const model::IdentifiedModel m = model::IdentifyTransferFunction(est.t, est.u, est.y, o, on.segments);
    if (!m.ok) throw Error(Located(args->data, "", "no model: " + m.reason));
    std::optional<Series> val;
    std::optional<ProcessOn> val_on;
    if (!args->validate.empty()) {
      val = read(args->validate);
      val_on = stretches(*val, args->validate);
    }
    PrintModel(m, o);
    std::printf("fit on estimation data: %.2f %%\n", m.fit_percent);
    double fit_val = NAN;
    if (val) {
      fit_val = model::ValidateFitPercent(m.tf, m.offset, val->t, val->u, val->y, val_on->segments);
      std::printf("fit on validation data (%s, initial state fitted): %.2f %%\n", args->validate.c_str(), fit_val);
    }
    std::printf("AIC %.6g  AICc %.6g  BIC %.6g  FPE %.6g  (%d parameters)\n", m.criteria.aic, m.criteria.aicc,
                m.criteria.bic, m.criteria.fpe, m.parameters);
    if (args->orders) {
      Series a = est, b = est;
      std::vector<Segment> sa = on.segments, sb = on.segments;
      if (val) {
        b = *val;
        sb = val_on->segments;
      } else {  // estimate on the first half, validate on the second
        const std::size_t h = est.t.size() / 2;
        a = {{est.t.begin(), est.t.begin() + h},
             {est.u.begin(), est.u.begin() + h},
             {est.y.begin(), est.y.begin() + h},
             0,
             {},
             {}};
        b = {{est.t.begin() + h, est.t.end()},
             {est.u.begin() + h, est.u.end()},
             {est.y.begin() + h, est.y.end()},
             0,
             {},
             {}};
        sa.clear();
        sb.clear();
        for (const Segment& s : on.segments) {
          if (s.begin < h) sa.push_back({s.begin, std::min(s.end, h), s.process_starts});
          // A stretch cut at the half goes on mid-process in the second half.
          if (s.end > h) sb.push_back({std::max(s.begin, h) - h, s.end - h, s.begin >= h && s.process_starts});
        }
      }
      std::printf("\n%6s %6s %12s %12s %12s %10s\n", "poles", "zeros", "fit_est_%", "fit_val_%", "AICc", "delay_s");
      for (const auto& r : model::OrderTable(a.t, a.u, a.y, b.t, b.u, b.y, o, sa, sb))
        std::printf("%6d %6d %12.2f %12.2f %12.6g %10.4f\n", r.poles, r.zeros, r.fit_estimation, r.fit_validation,
                    r.aicc, r.delay_s);
    }
    if (!args->out.empty()) {
      nlohmann::json j = ModelJson(m, o, args->input, args->output, est.t, on.segments, on.excluded);
      if (val) j["fit_validation_pct"] = fit_val;
      AtomicFile file(args->out);
      file.stream() << j.dump(2) << "\n";
      file.Commit();
      std::printf("wrote %s\n", args->out.c_str());
    }
    return 0;
  };
}

}  // namespace bead::tools
