// bead feedforward: the thesis' wheel feed-forward (chapter 4) as a
// command CSV the rig can play, from the identified models and the planned
// extruder command.
#include <cmath>
#include <cstdio>
#include <memory>

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

}  // namespace

Run AddFeedforward(CLI::App& app) {
  struct Args {
    std::string plan, time = "t_s", command = "extruder_cmd_v", flow_model, rpm_model, rig, out;
    double target_area = 14.0, rate_hz = 100.0;
    model::WheelModel wheel;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("feedforward", Summary("feedforward"));
  cmd->footer(
      "In:  the planned extruder command (a CSV or .mat: --time and --command name its columns), the models\n"
      "     of screw RPM -> flow (--flow-model, bead identify -o) and extruder voltage -> RPM (--rpm-model;\n"
      "     default the thesis' eq. 21), the wheel's first-order model (thesis 3.3.3; its diameter from\n"
      "     --rig), the target bead area.\n"
      "Out: -o a CSV at the controller's rate (--rate-hz): t_s, extruder_cmd_v, wheel_cmd_v (the command to\n"
      "     play), and what the models predict: flow, the wheel's surface speed, the area; the predicted\n"
      "     area's RMS deviation under the plan beside a constant wheel's (the thesis' Table 4 comparison:\n"
      "     six times less variation on its rig).\n"
      "Example:\n"
      "  bead feedforward --plan plan.csv --flow-model flow.json --rig rig.yaml --target-area 14 -o wheel.csv");
  cmd->add_option("--plan", args->plan, "Planned extruder command (CSV or .mat)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--time", args->time, "Its time column (s)")->capture_default_str();
  cmd->add_option("--command", args->command, "Its extruder command column (V)")->capture_default_str();
  cmd->add_option("--flow-model", args->flow_model, "Screw RPM -> flow model (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--rpm-model", args->rpm_model, "Extruder voltage -> RPM model (JSON; default thesis eq. 21)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rig", args->rig, "Rig file: the wheel's diameter")->check(CLI::ExistingFile);
  cmd->add_option("--target-area", args->target_area, "Bead area to hold (mm^2)")->capture_default_str();
  cmd->add_option("--rate-hz", args->rate_hz, "Controller rate (Hz)")->capture_default_str();
  cmd->add_option("--wheel-gain", args->wheel.gain_rpm_per_v, "Wheel RPM per volt")->capture_default_str();
  cmd->add_option("--wheel-tau", args->wheel.tau_s, "Wheel time constant (s)")->capture_default_str();
  cmd->add_option("--wheel-delay", args->wheel.delay_s, "Wheel delay (s)")->capture_default_str();
  cmd->add_option("-o,--out", args->out, "Wheel command CSV to write")->required();
  return [args]() {
    const model::TransferFunction r2q = OneInput(args->flow_model);
    const model::TransferFunction v2r =
        args->rpm_model.empty() ? model::ThesisVoltageToRpm() : OneInput(args->rpm_model);
    model::WheelModel wheel = args->wheel;
    if (!args->rig.empty()) wheel.radius_mm = ReadRig(args->rig).wheel_diameter_mm / 2;
    const ChannelColumns plan = ReadChannelColumns(args->plan, args->time, {args->command});
    PrintFileNote(plan.file_note);
    model::FeedForwardOptions o;
    o.target_area_mm2 = args->target_area;
    o.rate_hz = args->rate_hz;
    const control::WheelPlan p = control::PlanWheel(plan.t, plan.values[0], v2r, r2q, wheel, o);
    WritePlan(args->out, p);
    std::printf("%s: %zu ticks at %.4g Hz over %.4g s\n", args->plan.c_str(), p.t_s.size(), args->rate_hz,
                p.t_s.back() - p.t_s.front());
    std::printf(
        "predicted area: RMS deviation from %.4g mm^2 %.3f %% with the wheel fed forward, %.3f %% with a constant "
        "wheel: %.1f times less variation (the thesis measured about 6 on its rig)\n",
        args->target_area, 100 * p.rms_rel_planned, 100 * p.rms_rel_constant, p.rms_rel_constant / p.rms_rel_planned);
    std::printf("wrote %s\n", args->out.c_str());
    return 0;
  };
}

}  // namespace bead::tools
