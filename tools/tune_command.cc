// bead tune: a PID from a model file, by the method asked (or every one
// side by side), with the closed loop's figures on the model.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "libbead/control/controller_file.h"
#include "libbead/control/loop_check.h"
#include "libbead/control/pid_tuning.h"
#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/model/model_file.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {
namespace {

void PrintRow(const control::Evaluated& e) {
  const auto& d = e.design;
  std::printf("%-14s %11.6g %11.6g %11.6g %10.4g %8.3g %8.1f %6.2f %9.4g %10.4g %10.4g %10.4g\n", d.method.c_str(),
              d.pid.kp, d.pid.ki, d.pid.kd, d.stability_degree, e.margins.gain_margin, e.margins.phase_margin_deg,
              e.margins.ms, e.setpoint.overshoot_pct, e.setpoint.settling_s, e.setpoint.iae, e.load.iae);
}

// What the check says of a row: nothing when the loop passes; otherwise
// the reasons, under the row.
void PrintVerdict(const control::LoopVerdict& v) {
  if (!v.ok) std::printf("  ^ REFUSED: %s\n", v.Summary().c_str());
  if (v.conditionally_stable)
    std::printf("  ^ conditionally stable: the loop is unstable if its gain falls by a factor %.3g\n",
                v.lower_gain_margin);
}

void PrintHeader() {
  std::printf("%-14s %11s %11s %11s %10s %8s %8s %6s %9s %10s %10s %10s\n", "method", "kp", "ki", "kd", "J_1/s", "GM",
              "PM_deg", "Ms", "overshoot%", "settle_s", "IAE_step", "IAE_load");
}

struct TuneArgs {
  std::string model, method = "max-stability", out;
  double degree = 0, filter_n = 0;
  bool compare = false;
  control::LoopRequirements need;
};

// The design by `method`, its derivative filtered as asked.
control::Design DesignFor(const model::TransferFunction& g, const TuneArgs& a, const std::string& method) {
  const std::optional<double> degree = a.degree > 0 ? std::optional<double>(a.degree) : std::nullopt;
  control::Design d = control::DesignPid(g, method, method == "max-stability" ? degree : std::nullopt);
  control::FilterDerivative(g, d, a.filter_n);
  return d;
}

// Every method's row, each with the check's verdict under it.
void PrintComparison(const model::TransferFunction& g, const TuneArgs& a, const control::Design& chosen) {
  PrintHeader();
  for (const std::string& m : control::Methods()) {
    const control::Design d = m == a.method ? chosen : DesignFor(g, a, m);
    if (!d.ok) {
      std::printf("%-14s %s\n", m.c_str(), d.reason.c_str());
      continue;
    }
    const control::Evaluated e = control::Evaluate(g, d);
    PrintRow(e);
    PrintVerdict(control::CheckLoop(g, e, a.need));
  }
}

// The other methods whose loops pass, for a refusal's message.
std::string MethodsThatPass(const model::TransferFunction& g, const TuneArgs& a) {
  std::string pass;
  for (const std::string& m : control::Methods()) {
    if (m == a.method) continue;
    const control::Design d = DesignFor(g, a, m);
    if (d.ok && control::CheckLoop(g, control::Evaluate(g, d), a.need).ok) pass += (pass.empty() ? "" : ", ") + m;
  }
  return pass;
}

int Tune(const TuneArgs& a) {
  if (!a.out.empty()) CheckWritable(a.out);
  const model::ModelFile f = model::ReadModelFile(a.model);
  if (f.tfs.size() != 1)
    throw Error(Located(a.model, "inputs", "a model of several inputs: tune takes a model of one input"));
  const model::TransferFunction& g = f.tfs[0];
  std::printf("%s: %s\n", a.model.c_str(),
              g.delay_s > 0 ? ("delay " + std::to_string(g.delay_s) + " s").c_str() : "no delay");
  std::printf("derivative: %s\n", a.filter_n > 0 ? "filtered, Tf = kd / (N kp)" : "ideal (seed 004 eq. 16)");
  const control::Design chosen = DesignFor(g, a, a.method);
  if (a.compare) PrintComparison(g, a, chosen);
  if (!chosen.ok) throw Error(Located(a.model, "", a.method + ": no controller written: " + chosen.reason));
  const control::Evaluated e = control::Evaluate(g, chosen);
  const control::LoopVerdict verdict = control::CheckLoop(g, e, a.need);
  if (!a.compare) {
    PrintHeader();
    PrintRow(e);
    PrintVerdict(verdict);
  }
  if (!chosen.note.empty()) std::printf("%s: %s\n", chosen.method.c_str(), chosen.note.c_str());
  if (!chosen.fopdt.how.empty())
    std::printf("first order plus delay (%s): k %.5g, tau %.4g s, theta %.4g s\n", chosen.fopdt.how.c_str(),
                chosen.fopdt.k, chosen.fopdt.tau_s, chosen.fopdt.theta_s);
  if (!verdict.ok) {
    const std::string pass = MethodsThatPass(g, a);
    throw Error(Located(a.model, "",
                        a.method + ": no controller written: " + verdict.Summary() +
                            (pass.empty() ? "" : " (methods that pass: " + pass + ")")));
  }
  if (!a.out.empty()) {
    control::WriteControllerFile(a.out, e, g, a.model);
    std::printf("wrote %s\n", a.out.c_str());
  }
  std::printf("kp=%.6g ki=%.6g kd=%.6g stability_degree=%.6g\n", chosen.pid.kp, chosen.pid.ki, chosen.pid.kd,
              chosen.stability_degree);
  return 0;
}

}  // namespace

Run AddTune(CLI::App& app) {
  auto args = std::make_shared<TuneArgs>();
  CLI::App* cmd = app.add_subcommand("tune", Summary("tune"));
  cmd->footer(
      "In:  a model file of `bead identify -o` (one input: a transfer function or process model, with or\n"
      "     without delay).\n"
      "Methods: max-stability (seed 004: the PID kp + ki/s + kd s whose closed loop's rightmost root lies\n"
      "     furthest left; J is minus its real part), simc (Skogestad 2003), imc (Rivera, Morari & Skogestad\n"
      "     1986), zn (Ziegler-Nichols' reaction curve, 1942), cohen-coon (1953); the rules on the model's\n"
      "     first-order-plus-delay form (its own, Skogestad's half rule, or seed 004's step identification).\n"
      "Out: the gains, J (the rightmost closed-loop root with the gains as printed: rounding splits a\n"
      "     multiple root), gain and phase margins, the peak sensitivity Ms, a unit setpoint step\n"
      "     (overshoot, settling to +-5 % as seed 004 uses, IAE) and a unit load step at the plant's input\n"
      "     (IAE), simulated on the model with its delay exact. The derivative: ideal (eq. 16) unless\n"
      "     --filter N sets Tf = kd / (N kp). --compare prints every method's row; -o writes the\n"
      "     controller (YAML, atomically). The last line: kp=<v> ki=<v> kd=<v> stability_degree=<v>.\n"
      "Checked: a controller is written only when its closed loop is stable (J > --min-degree), well posed\n"
      "     (an ideal derivative on a model with a direct feedthrough is not: give --filter), with Ms <=\n"
      "     --max-ms and a gain margin >= --min-gain-margin (a conditionally stable loop is said as such);\n"
      "     otherwise exit 1 with the reasons. --compare marks every row that fails (REFUSED).\n"
      "Examples:\n"
      "  bead identify step.csv --time t --input u --output temp --structure P2D -o heater.json\n"
      "  bead tune heater.json --compare\n"
      "  bead tune heater.json --method max-stability -o heater_pid.yaml");
  cmd->add_option("model", args->model, "Model JSON (bead identify -o)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--method", args->method, "max-stability, simc, imc, zn or cohen-coon")->capture_default_str();
  cmd->add_option("--degree", args->degree,
                  "max-stability: place a triple root at -J for this J (1/s, > 0) instead of maximising J")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--filter", args->filter_n, "Derivative filter: Tf = kd / (N kp), N > 0 (absent: ideal derivative)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--min-degree", args->need.min_degree, "Required J: the rightmost closed-loop root left of -J, 1/s")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--max-ms", args->need.max_ms, "Largest peak sensitivity Ms allowed")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--min-gain-margin", args->need.min_gain_margin, "Smallest gain margin allowed (factor)")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->add_flag("--compare", args->compare, "Every method side by side");
  cmd->add_option("-o,--out", args->out, "Controller YAML to write");
  return [args]() { return Tune(*args); };
}

}  // namespace bead::tools
