// bead explain, run mode: a run archive measured, its flow against a model
// of flow from screw speed (explain/run_explain.h does the work).
#include <cstdio>
#include <memory>
#include <optional>

#include "calibration/pin_offset.h"
#include "libbead/archive/measured_run.h"
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

namespace bead::tools {

int ExplainRunMode(const ExplainArgs& a) {
  const ExplainArgs* args = &a;
  const explain::ExplainOptions options = a.Explain();
  // A model file that cannot serve is said before the run is measured.
  if (!a.model.empty() && model::ReadModelFile(a.model).tfs.size() != 1)
    throw Error(Located(a.model, "inputs", "run mode takes a model of flow from the screw speed alone (one input)"));
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
    for (const std::string& w : m->flow.warnings) std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), w.c_str());
    for (const auto& s : m->flow.samples)
      if (s.valid) m->t.push_back(s.t_s), m->u.push_back(s.screw_rpm), m->y.push_back(s.flow_mm3_s);
    if (m->t.size() < 50) throw Error(Located(path, "", "fewer than 50 profiles with a flow: nothing to explain"));
    return m;
  };
  const auto main_run = measure(args->data);
  // The base model identified at the rate the loop explains (a long run's
  // flow averaged over bins of profiles).
  const std::size_t bin = a.profiles_per_sample ? a.profiles_per_sample : explain::ExplainBinOf(main_run->flow);
  if (bin > 1)
    std::printf("%s: a long run: explained at %zu profiles per sample (%zu samples)\n", args->data.c_str(), bin,
                main_run->t.size() / bin);
  const BaseModel mdl =
      ModelFor(a, explain::AverageInBins(main_run->t, bin), {explain::AverageInBins(main_run->u, bin)},
               explain::AverageInBins(main_run->y, bin), {}, args->data);
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
  run_options.profiles_per_sample = bin;
  const explain::MeasuredFlow main_view = view(*main_run, args->data);
  const explain::MeasuredFlow other_view = other ? view(*other, args->validate) : explain::MeasuredFlow{};
  std::printf("%s: explaining the flow in extrusion time...\n", args->data.c_str());
  const explain::RunExplanation e =
      explain::ExplainMeasuredRun(rig, main_view, other ? &other_view : nullptr, mdl.tfs[0], mdl.offset, run_options);
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
  const nlohmann::json j = explain::RunJson(e, rig, mdl.tfs[0], mdl.offset, mdl.source, pins, args->flow_out);
  WriteJson(args->out, j);
  return 0;
}

}  // namespace bead::tools
