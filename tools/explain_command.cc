// bead explain: close the loop - flow (or any measured series) against a
// model, residual diagnostics, the effects the model lacks added one at a
// time when they earn it, and the error before and after.
#include <memory>

#include "libbead/io/atomic_file.h"
#include "libbead/io/run_archive.h"
#include "tools/commands.h"
#include "tools/explain_modes.h"
#include "tools/occlusion_step.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddExplain(CLI::App& app) {
  auto args = std::make_shared<ExplainArgs>();
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
      "Part mode: bead explain --rig RIG.yaml PART.h5 [--validate OTHER.h5] -o explain.json\n"
      "  a part scan (format 1.1): its flow along the toolpath (bead flow's, Q = v_head A in the time the\n"
      "  nozzle laid each place) is the series, the screw's RPM the input; the loop as in CSV mode, the\n"
      "  head's speed tried as a recorded cause (--channels to name others, --no-channels for none).\n"
      "CSV mode:  bead explain DATA.csv --input COL --output COL [--time COL] [--validate OTHER.csv]\n"
      "  (--input a,b: a base model with several inputs, a transfer function each; --model of as many)\n"
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
  cmd->add_option("--input", args->inputs, "CSV mode: input column (several: a,b)")->delimiter(',');
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
  cmd->add_option("--profiles-per-sample", args->profiles_per_sample,
                  "Run mode: profiles averaged into each sample explained (0: enough that a long run keeps at most "
                  "16384 samples, never under 25 Hz)")
      ->capture_default_str();
  cmd->add_option("--max-effects", args->max_effects, "At most this many effects")->capture_default_str();
  cmd->add_option("-o,--out", args->out, "explain.json to write (atomically)")->required();
  AddOcclusionOption(cmd, args->occlusion);
  return [args]() {
    CheckWritable(args->out);  // before the run is measured
    if (!args->flow_out.empty()) CheckWritable(args->flow_out);
    if (args->rig.empty()) return ExplainSeriesMode(*args);
    if (IsPartScanFile(args->data)) return ExplainPartMode(*args);
    return ExplainRunMode(*args);
  };
}

}  // namespace bead::tools
