// MeasureRunFlow: a run archive measured and its flow Q = v A computed in
// one call, for every command that needs both (bead flow, batch, report,
// explain). Streamed in fixed memory when it can be (streamed_flow.h),
// else the whole run in memory (measured_run.h, then ComputeFlow): the
// same samples either way. A streamed attempt that cannot finish (a wheel
// standing still longer than the history kept) is redone whole; its
// outputs are not committed, and `whole_run_why` says why.
#pragma once

#include <string>
#include <vector>

#include "libbead/archive/measure_run.h"
#include "libbead/archive/measured_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/core/worker_pool.h"
#include "libbead/flow/flow.h"

namespace bead {

struct RunFlowRequest {
  MeasureRunOptions measure;
  FlowOptions flow;
  // Written atomically when named: the geometry CSV (every profile) and
  // the flow CSV (not written when the run has no flow).
  std::string geometry_csv, flow_csv;
  // Keep the measured run and its flow in memory (RunFlow::whole, ::flow):
  // for the stages that need the whole series. Never streamed then.
  bool keep = false;
  // A run without the wheel's motion: an Error naming the file and dataset
  // (true), or the geometry alone and RunFlow::gap saying why (false).
  bool require_motion = true;
  std::string needs = "the flow";  // what needs the motion, for the messages
};

struct RunFlow {
  MeasureRunSummary measure;
  MotionGap gap;  // not none: no flow, and why
  bool streamed = false;
  std::string whole_run_why;  // why a streamed attempt was redone whole (empty: it was not)
  std::size_t samples = 0, valid = 0;
  double total_volume_mm3 = 0.0;
  int area_outliers = 0, speed_outliers = 0, encoder_repairs = 0;
  std::vector<std::string> warnings;  // the flow's (FlowResult::warnings)
  // With RunFlowRequest::keep only:
  MeasuredRun whole;
  FlowResult flow;
};

RunFlow MeasureRunFlow(const std::string& path, const Rig& rig, WorkerPool& pool, const RunFlowRequest& request);

}  // namespace bead
