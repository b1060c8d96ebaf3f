// bead feedforward: the thesis' wheel feed-forward (chapter 4) as a
// command CSV the rig can play, from the identified models and the planned
// extruder command.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "tools/rig_input.h"
#include "libbead/control/feed_forward_plan.h"
#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/series_columns.h"
#include "libbead/model/model_file.h"
#include "tools/commands.h"
#include "tools/series_stretches.h"
#include "tools/subcommands.h"

namespace bead::tools {
namespace {

model::TransferFunction OneInput(const std::string& path) {
  const model::ModelFile f = model::ReadModelFile(path);
  if (f.tfs.size() != 1) throw Error(Located(path, "inputs", "a model of several inputs: give one of one input"));
  return f.tfs[0];
}

void WritePlan(const std::string& path, const control::WheelPlan& p) {
  AtomicFile out(path);
  out.stream() << "t_s,extruder_cmd_v,wheel_cmd_v,predicted_flow_mm3_s,predicted_speed_mm_s,predicted_area_mm2\n";
  for (std::size_t i = 0; i < p.t_s.size(); ++i) {
    std::string line;
    for (double v :
         {p.t_s[i], p.extruder_cmd_v[i], p.wheel_cmd_v[i], p.flow_mm3_s[i], p.speed_mm_s[i], p.area_mm2[i]}) {
      if (!line.empty()) line += ',';
      AppendCsvNumber(line, v);
    }
    out.stream() << line << "\n";
  }
  out.Commit();
}

// The wheel's first-order model (thesis 3.3.3) from an identified model
// of one pole and no zero (wheel volts -> RPM): K / (tau s + 1) e^(-Td s).
model::WheelModel WheelFromModel(const std::string& path) {
  const model::TransferFunction tf = OneInput(path).Monic();
  if (tf.poles() != 1 || tf.zeros() != 0 || !(tf.den[1] > 0))
    throw Error(Located(path, "",
                        "the wheel's model must have one stable pole and no zero (bead identify --poles 1 --zeros 0 "
                        "on a wheel step: wheel_cmd_v -> wheel RPM)"));
  model::WheelModel w;
  w.gain_rpm_per_v = tf.DcGain();
  w.tau_s = 1.0 / tf.den[1];
  w.delay_s = tf.delay_s;
  return w;
}

// The target: the median area of a measured run's valid rows (a bead
// flow or bead measure CSV), corrected where the file has it.
double MedianArea(const std::string& path) {
  CsvReader csv(path);
  const std::vector<std::string> header = csv.Header({}, "flow or geometry CSV");
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const int corrected = column("area_corrected_mm2"), plain = column("area_mm2"), valid = column("valid");
  if (plain < 0) throw Error(Located(path, "header", "has no area_mm2 column (a bead flow or bead measure CSV)"));
  std::vector<double> areas;
  auto number = [&](int i, const char* name) {
    const auto k = static_cast<std::size_t>(i);
    return i < 0 || k >= csv.columns() || csv.Empty(k) ? NAN : csv.Double(k, name);
  };
  while (csv.Next()) {
    if (valid >= 0 && number(valid, "valid") != 1.0) continue;
    double a = number(corrected, "area_corrected_mm2");
    if (!std::isfinite(a)) a = number(plain, "area_mm2");
    if (std::isfinite(a)) areas.push_back(a);
  }
  if (areas.empty()) throw Error(Located(path, "", "holds no valid area to take the target from"));
  std::nth_element(areas.begin(), areas.begin() + static_cast<long>(areas.size() / 2), areas.end());
  return areas[areas.size() / 2];
}

struct FeedforwardArgs {
  std::string plan, time = "t_s", command = "extruder_cmd_v", flow_model, rpm_model, wheel_model, rig, target_from, out;
  double target_area = NAN, rate_hz = 100.0;
  double wheel_gain = NAN, wheel_tau = NAN, wheel_delay = NAN;
  bool thesis_rpm = false, thesis_wheel = false;
};

// The wheel as the user's files give it; the thesis rig's constants only
// when asked for by name.
model::WheelModel WheelFor(const FeedforwardArgs& a) {
  model::WheelModel wheel;  // the thesis' 3.3.3 constants
  const bool given = std::isfinite(a.wheel_gain) || std::isfinite(a.wheel_tau) || std::isfinite(a.wheel_delay);
  if (int(!a.wheel_model.empty()) + int(given) + int(a.thesis_wheel) != 1)
    throw CLI::ValidationError("wheel",
                               "give the wheel's model once: --wheel-model WHEEL.json (bead identify --poles 1 "
                               "--zeros 0 on a wheel step), --wheel-gain, --wheel-tau and --wheel-delay, or "
                               "--thesis-wheel for the thesis rig's (2.517 RPM/V, 0.0377 s, 0.009 s)");
  if (!a.wheel_model.empty()) wheel = WheelFromModel(a.wheel_model);
  if (given) {
    if (!(a.wheel_gain > 0 && a.wheel_tau > 0 && a.wheel_delay >= 0))
      throw CLI::ValidationError("--wheel-gain/--wheel-tau/--wheel-delay",
                                 "give all three: a gain and time constant above 0, a delay of 0 or more");
    wheel.gain_rpm_per_v = a.wheel_gain, wheel.tau_s = a.wheel_tau, wheel.delay_s = a.wheel_delay;
  }
  if (!a.rig.empty())
    wheel.radius_mm = ReadRigSaying(a.rig).wheel_diameter_mm / 2;
  else if (!a.thesis_wheel)
    throw CLI::RequiredError("--rig (the wheel's diameter)");
  return wheel;
}

void AddFeedforwardOptions(CLI::App* cmd, FeedforwardArgs& a) {
  cmd->add_option("--plan", a.plan, "Planned extruder command (CSV or .mat)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--time", a.time, "Its time column (s)")->capture_default_str();
  cmd->add_option("--command", a.command, "Its extruder command column (V)")->capture_default_str();
  cmd->add_option("--flow-model", a.flow_model, "Screw RPM -> flow model (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--rpm-model", a.rpm_model, "Extruder voltage -> RPM model (JSON)")->check(CLI::ExistingFile);
  cmd->add_flag("--thesis-rpm-model", a.thesis_rpm, "Use the thesis' eq. 21 as the voltage -> RPM model");
  cmd->add_option("--rig", a.rig, "Rig file: the wheel's diameter")->check(CLI::ExistingFile);
  cmd->add_option("--target-area", a.target_area, "Bead area to hold (mm^2)")->check(CLI::PositiveNumber);
  cmd->add_option("--target-from", a.target_from, "Hold the median area of this measured run (flow or geometry CSV)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rate-hz", a.rate_hz, "Controller rate (Hz)")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--wheel-model", a.wheel_model, "Wheel volts -> RPM model (JSON: one pole, no zero)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--wheel-gain", a.wheel_gain, "Wheel RPM per volt");
  cmd->add_option("--wheel-tau", a.wheel_tau, "Wheel time constant (s)");
  cmd->add_option("--wheel-delay", a.wheel_delay, "Wheel delay (s)");
  cmd->add_flag("--thesis-wheel", a.thesis_wheel, "Use the thesis rig's wheel (3.3.3) and its 254.762 mm diameter");
  cmd->add_option("-o,--out", a.out, "Wheel command CSV to write")->required();
}

}  // namespace

Run AddFeedforward(CLI::App& app) {
  auto args = std::make_shared<FeedforwardArgs>();
  CLI::App* cmd = app.add_subcommand("feedforward", Summary("feedforward"));
  cmd->footer(
      "In:  the planned extruder command (a CSV or .mat: --time and --command name its columns), the models\n"
      "     of screw RPM -> flow (--flow-model) and extruder voltage -> RPM (--rpm-model), both from bead\n"
      "     identify, the wheel's first-order model (--wheel-model, or --wheel-gain/--wheel-tau/\n"
      "     --wheel-delay; thesis 3.3.3) and its diameter (--rig), the target bead area (--target-area, or\n"
      "     --target-from a measured run's flow CSV). The thesis rig's constants only by name:\n"
      "     --thesis-rpm-model (eq. 21), --thesis-wheel.\n"
      "Out: -o a CSV at the controller's rate (--rate-hz): t_s, extruder_cmd_v, wheel_cmd_v (the command to\n"
      "     play), and what the models predict: flow, the wheel's surface speed, the area; the predicted\n"
      "     area's RMS deviation under the plan beside a constant wheel's (the thesis' Table 4 comparison:\n"
      "     six times less variation on its rig).\n"
      "Example:\n"
      "  bead feedforward --plan plan.csv --flow-model flow.json --rpm-model rpm.json --wheel-model wheel.json\n"
      "     --rig rig.yaml --target-from flow.csv -o wheel.csv");
  AddFeedforwardOptions(cmd, *args);
  return [args]() {
    if (args->rpm_model.empty() == !args->thesis_rpm)
      throw CLI::ValidationError("--rpm-model",
                                 "give --rpm-model V2R.json (bead identify: extruder_cmd_v -> "
                                 "screw_rpm, from bead export --log) or --thesis-rpm-model, once");
    if (std::isfinite(args->target_area) == !args->target_from.empty())
      throw CLI::ValidationError("--target-area",
                                 "give the area to hold once: --target-area MM2 or --target-from "
                                 "FLOW.csv (a measured run)");
    CheckWritable(args->out);
    const model::TransferFunction r2q = OneInput(args->flow_model);
    const model::TransferFunction v2r = args->thesis_rpm ? model::ThesisVoltageToRpm() : OneInput(args->rpm_model);
    const model::WheelModel wheel = WheelFor(*args);
    const double target = args->target_from.empty() ? args->target_area : MedianArea(args->target_from);
    if (!args->target_from.empty())
      std::printf("target area: %.4g mm^2, the median of %s\n", target, args->target_from.c_str());
    const ChannelColumns plan = ReadChannelColumns(args->plan, args->time, {args->command});
    PrintFileNote(plan.file_note);
    model::FeedForwardOptions o;
    o.target_area_mm2 = target;
    o.rate_hz = args->rate_hz;
    const control::WheelPlan p = control::PlanWheel(plan.t, plan.values[0], v2r, r2q, wheel, o);
    WritePlan(args->out, p);
    std::printf("%s: %zu ticks at %.4g Hz over %.4g s\n", args->plan.c_str(), p.t_s.size(), args->rate_hz,
                p.t_s.back() - p.t_s.front());
    std::printf(
        "predicted area: RMS deviation from %.4g mm^2 %.3f %% with the wheel fed forward, %.3f %% with a constant "
        "wheel: %.1f times less variation (the thesis measured about 6 on its rig)\n",
        target, 100 * p.rms_rel_planned, 100 * p.rms_rel_constant, p.rms_rel_constant / p.rms_rel_planned);
    std::printf("wrote %s\n", args->out.c_str());
    return 0;
  };
}

}  // namespace bead::tools
