#include "libbead/archive/run_flow.h"

#include <optional>

#include "libbead/archive/streamed_flow.h"
#include "libbead/core/error.h"
#include "libbead/io/flow_csv.h"
#include "libbead/io/geometry_csv.h"

namespace bead {
namespace {

// A geometry CSV when named, committed only when the pass completes.
struct GeometrySink {
  std::optional<GeometryCsvWriter> writer;
  explicit GeometrySink(const std::string& path) {
    if (!path.empty()) writer.emplace(path);
  }
  std::function<void(const GeometryRow&)> Row() {
    if (!writer) return {};
    return [this](const GeometryRow& row) { writer->Append(row); };
  }
  void Commit() {
    if (writer) writer->Commit();
  }
};

void TakeFlowFigures(const FlowResult& flow, RunFlow& out) {
  out.samples = flow.samples.size();
  for (const FlowSample& s : flow.samples) out.valid += s.valid;
  out.total_volume_mm3 = flow.total_volume_mm3;
  out.area_outliers = flow.area_outliers, out.speed_outliers = flow.speed_outliers;
  out.encoder_repairs = flow.encoder_repairs;
  out.warnings = flow.warnings;
}

// In fixed memory; false when the run needs its whole log (out.whole_run_why).
bool Streamed(OpenedRun opened, const std::string& path, const Rig& rig, WorkerPool& pool, const RunFlowRequest& r,
              RunFlow& out) {
  GeometrySink geometry(r.geometry_csv);
  std::optional<FlowCsvWriter> flow;
  if (!r.flow_csv.empty()) flow.emplace(r.flow_csv);
  const StreamedFlow f = StreamRunFlow(
      std::move(opened), path, rig, pool, r.measure, r.flow,
      [&](const FlowSample& s) {
        if (flow) flow->Append(s);
      },
      geometry.Row());
  if (!f.complete) {
    out.whole_run_why = f.why;
    return false;
  }
  geometry.Commit();
  if (flow) flow->Commit();
  out.streamed = true;
  out.measure = f.measure;
  out.samples = f.samples, out.valid = f.valid, out.total_volume_mm3 = f.total_volume_mm3;
  out.area_outliers = f.area_outliers, out.speed_outliers = f.speed_outliers, out.encoder_repairs = f.encoder_repairs;
  out.warnings = f.warnings;
  return true;
}

// The whole run in memory, then its flow (when the run has the motion).
void Whole(const std::string& path, const Rig& rig, WorkerPool& pool, const RunFlowRequest& r, RunFlow& out) {
  OpenedRun opened = OpenRun(path, pool);
  out.gap = MissingMotion(opened.run, r.needs);
  if (!out.gap.none() && r.require_motion) throw Error(Located(path, out.gap.dataset, out.gap.why));
  GeometrySink geometry(r.geometry_csv);
  MeasuredRun m = MeasureWholeRun(std::move(opened), rig, pool, r.measure, geometry.Row());
  geometry.Commit();
  out.measure = m.summary;
  if (out.gap.none()) {
    FlowResult flow = ComputeFlow(rig, m.run.profiles, m.geometry, *m.run.log, r.flow, m.corrected, m.sigma);
    if (!r.flow_csv.empty()) WriteFlowCsv(r.flow_csv, flow);
    TakeFlowFigures(flow, out);
    if (r.keep) out.flow = std::move(flow);
  }
  if (r.keep) out.whole = std::move(m);
}

}  // namespace

RunFlow MeasureRunFlow(const std::string& path, const Rig& rig, WorkerPool& pool, const RunFlowRequest& request) {
  RunFlow out;
  // Streamed when it can be: not kept, and no whole-run option (the area
  // smoothing); the whole-run path opens the run itself.
  if (!request.keep && StreamableFlow(request.flow)) {
    OpenedRun opened = OpenRun(path, pool, /*with_log=*/false);
    out.gap = MissingMotionUnread(opened, path, request.needs);
    if (!out.gap.none()) {
      if (request.require_motion) throw Error(Located(path, out.gap.dataset, out.gap.why));
      // No flow: the geometry alone, streamed.
      GeometrySink geometry(request.geometry_csv);
      out.measure = MeasureRun(*opened.profiles, rig, pool, request.measure, geometry.Row());
      geometry.Commit();
      return out;
    }
    if (Streamed(std::move(opened), path, rig, pool, request, out)) return out;
  }
  Whole(path, rig, pool, request, out);
  return out;
}

}  // namespace bead
