// bead explain, run mode: a run archive measured, its flow against a model
// of flow from screw speed (explain/run_explain.h does the work).
#include <cstdio>
#include <memory>
#include <optional>

#include "calibration/pin_offset.h"
#include "tools/rig_input.h"
#include "libbead/archive/run_flow.h"
#include "libbead/core/error.h"
#include "libbead/explain/explain_json.h"
#include "libbead/flow/flow.h"
#include "libbead/io/flow_csv.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/model/model_file.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "tools/explain_modes.h"
#include "tools/occlusion_step.h"
#include "tools/tty_progress.h"

namespace bead::tools {

int ExplainRunMode(const ExplainArgs& a) {
  const ExplainArgs* args = &a;
  const explain::ExplainOptions options = a.Explain();
  // A model file that cannot serve is said before the run is measured.
  if (!a.model.empty() && model::ReadModelFile(a.model).tfs.size() != 1)
    throw Error(Located(a.model, "inputs", "run mode takes a model of flow from the screw speed alone (one input)"));
  const Rig rig = ReadRigSaying(args->rig);
  // A run measured and its flow in extrusion time, kept in memory.
  struct Measured {
    RunFlow run;
    std::size_t valid = 0;  // samples with a flow
  };
  WorkerPool pool;
  RunFlowRequest request;
  request.measure.occlusion = ParseOcclusionMode(args->occlusion);
  request.measure.estimate = occlusion::EstimateOcclusion;
  request.measure.progress = TtyProgress("measured");
  request.keep = true;
  request.needs = "explain";
  auto measure = [&](const std::string& path) {
    auto m = std::make_unique<Measured>();
    m->run = MeasureRunFlow(path, rig, pool, request);
    if (const std::string line = OcclusionLine(m->run.measure); !line.empty()) std::printf("%s\n", line.c_str());
    for (const std::string& w : m->run.warnings) std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), w.c_str());
    for (const auto& s : m->run.flow.samples) m->valid += s.valid;
    if (m->valid < 50) throw Error(Located(path, "", "fewer than 50 profiles with a flow: nothing to explain"));
    return m;
  };
  const auto main_run = measure(args->data);
  // The base model identified at the rate the loop explains (a long run's
  // flow averaged over bins of profiles).
  const std::size_t bin = a.profiles_per_sample ? a.profiles_per_sample : explain::ExplainBinOf(main_run->run.flow);
  if (bin > 1)
    std::printf("%s: a long run: explained at %zu profiles per sample (%zu samples)\n", args->data.c_str(), bin,
                main_run->valid / bin);
  std::unique_ptr<Measured> other;
  if (!args->validate.empty()) other = measure(args->validate);
  auto view = [](const Measured& m, const std::string& path) {
    const MeasuredRun& w = m.run.whole;
    return explain::MeasuredFlow{path, &w.run.profiles, &w.geometry, &*w.run.log, &m.run.flow, &w.corrected, &w.sigma};
  };
  explain::RunExplainOptions run_options;
  run_options.explain = options;
  run_options.channels = args->channels;
  run_options.no_channels = args->no_channels;
  run_options.correct_flow = !args->flow_out.empty();
  run_options.profiles_per_sample = bin;
  const explain::MeasuredFlow main_view = view(*main_run, args->data);
  const explain::MeasuredFlow other_view = other ? view(*other, args->validate) : explain::MeasuredFlow{};
  std::printf("%s: explaining the flow in extrusion time...\n", args->data.c_str());
  const explain::IdentifiedRun run = ExplainWithModel(a, rig, main_view, other ? &other_view : nullptr, run_options);
  const explain::BaseModel& mdl = run.model;
  const explain::RunExplanation& e = run.explanation;
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
  nlohmann::json j = explain::RunJson(e, rig, mdl.tfs[0], mdl.offset, mdl.source, pins, args->flow_out);
  if (run.reidentified) j["offset_profile_reidentified"] = explain::ReidentifiedJson(*run.reidentified);
  WriteJson(args->out, j);
  return 0;
}

}  // namespace bead::tools
