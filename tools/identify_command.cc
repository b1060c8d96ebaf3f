#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/model/identify.h"
#include "tools/commands.h"
#include "tools/csv_columns.h"

namespace bead::tools {
namespace {

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

Run AddIdentify(CLI::App& app) {
  struct Args {
    std::string data, input, output, time, delay = "auto", validate, out;
    int poles = 2, zeros = 1;
    double max_delay_s = 1.0;
    bool orders = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("identify", "Identify a transfer function (poles, zeros, delay) from data");
  cmd->footer(
      "In:  any CSV with a header row; --input and --output name its columns, --time the time column\n"
      "     (seconds; without it, rows are unit-spaced). Rows with an empty field are skipped as gaps;\n"
      "     the model starts from rest, so give deviations from the operating point.\n"
      "Out: the model, MATLAB-style fit % on estimation (and validation) data, AIC/AICc/BIC/FPE;\n"
      "     with --orders the thesis Table 3 (poles 1-3, zeros 0-2), validated on --validate or on\n"
      "     the second half of DATA; -o a JSON model file (written atomically).\n"
      "Example:\n"
      "  bead identify flow.csv --time t_s --input screw_rpm --output flow_mm3_s --poles 2 --zeros 2 -o model.json");
  cmd->add_option("data", args->data, "Data CSV")->required()->check(CLI::ExistingFile);
  cmd->add_option("--input", args->input, "Input column")->required();
  cmd->add_option("--output", args->output, "Output column")->required();
  cmd->add_option("--time", args->time, "Time column (s)");
  cmd->add_option("--poles", args->poles, "Number of poles")->capture_default_str()->check(CLI::Range(1, 6));
  cmd->add_option("--zeros", args->zeros, "Number of zeros (<= poles)")->capture_default_str()->check(CLI::Range(0, 6));
  cmd->add_option("--delay", args->delay, "Input delay: auto or seconds")->capture_default_str();
  cmd->add_option("--max-delay-s", args->max_delay_s, "Largest delay searched by --delay auto")->capture_default_str();
  cmd->add_option("--validate", args->validate, "Validation CSV (same columns)")->check(CLI::ExistingFile);
  cmd->add_flag("--orders", args->orders, "Print the order-selection table");
  cmd->add_option("-o,--out", args->out, "Model JSON to write");
  return [args]() {
    const Series est = ReadColumns(args->data, args->time, args->input, args->output);
    model::IdentifyOptions o;
    o.poles = args->poles;
    o.zeros = args->zeros;
    o.max_delay_s = args->max_delay_s;
    if (args->delay != "auto") {
      try {
        o.delay_s = std::stod(args->delay);
      } catch (const std::exception&) {
        throw Error("--delay must be 'auto' or a number of seconds, got '" + args->delay + "'");
      }
    }
    std::printf("%s: %zu rows (%d skipped as gaps)\n", args->data.c_str(), est.t.size(), est.skipped);
    const model::IdentifiedModel m = model::IdentifyTransferFunction(est.t, est.u, est.y, o);
    if (!m.ok) throw Error(Located(args->data, "", "no model: " + m.reason));
    std::optional<Series> val;
    if (!args->validate.empty()) val = ReadColumns(args->validate, args->time, args->input, args->output);
    std::printf("model: (%s) / (%s) * exp(-%.4g s)\n", Polynomial(m.tf.num).c_str(), Polynomial(m.tf.den).c_str(),
                m.tf.delay_s);
    std::printf("DC gain %.6g; poles:", m.tf.DcGain());
    for (std::size_t k = 0; k < m.poles_real.size(); ++k) std::printf(" %.4g%+.4gi", m.poles_real[k], m.poles_imag[k]);
    std::printf("\nfit on estimation data: %.2f %%\n", m.fit_percent);
    double fit_val = NAN;
    if (val) {
      fit_val = model::ValidateFitPercent(m.tf, val->t, val->u, val->y);
      std::printf("fit on validation data (%s): %.2f %%\n", args->validate.c_str(), fit_val);
    }
    std::printf("AIC %.6g  AICc %.6g  BIC %.6g  FPE %.6g  (%d parameters)\n", m.criteria.aic, m.criteria.aicc,
                m.criteria.bic, m.criteria.fpe, m.parameters);
    if (args->orders) {
      Series a = est, b = est;
      if (val) {
        b = *val;
      } else {  // estimate on the first half, validate on the second
        const std::size_t h = est.t.size() / 2;
        a = {{est.t.begin(), est.t.begin() + h}, {est.u.begin(), est.u.begin() + h}, {est.y.begin(), est.y.begin() + h}};
        b = {{est.t.begin() + h, est.t.end()}, {est.u.begin() + h, est.u.end()}, {est.y.begin() + h, est.y.end()}};
        const double t0 = b.t.front();
        for (double& x : b.t) x -= t0;
      }
      std::printf("\n%6s %6s %12s %12s %12s\n", "poles", "zeros", "fit_est_%", "fit_val_%", "AICc");
      for (const auto& r : model::OrderTable(a.t, a.u, a.y, b.t, b.u, b.y, o))
        std::printf("%6d %6d %12.2f %12.2f %12.6g\n", r.poles, r.zeros, r.fit_estimation, r.fit_validation, r.aicc);
    }
    if (!args->out.empty()) {
      nlohmann::json j = {{"input", args->input},         {"output", args->output},
                          {"num", m.tf.num},              {"den", m.tf.den},
                          {"delay_s", m.tf.delay_s},      {"poles", o.poles},
                          {"zeros", o.zeros},             {"parameters", m.parameters},
                          {"fit_estimation_pct", m.fit_percent},
                          {"aic", m.criteria.aic},        {"aicc", m.criteria.aicc},
                          {"bic", m.criteria.bic},        {"fpe", m.criteria.fpe},
                          {"poles_real", m.poles_real},   {"poles_imag", m.poles_imag}};
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
