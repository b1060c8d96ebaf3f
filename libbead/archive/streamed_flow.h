// StreamRunFlow: a run archive's flow in fixed memory, the same samples as
// MeasureWholeRun + ComputeFlow (flow.h) bit for bit. Nothing of the run is
// held whole:
//  1. the log is walked (LogStream) for what the batch takes from all of it:
//     the median step and the encoder's glitch threshold (exact medians by
//     repeated walks, core/median_by_walks.h);
//  2. the profiles are measured window by window (MeasureRun) and each
//     row's few numbers the flow needs go to a scratch file (56 bytes a
//     profile, in $TMPDIR or /tmp), from which the area floor's median is walked;
//  3. the rows and the log, interleaved in time, go through StreamingFlow
//     given those whole-run facts; each sample is handed on as it is done.
// Memory: the measuring windows, history_s of log (StreamingFlow) and
// fixed buffers, whatever the run's length. An extrusion time older than
// history_s (a wheel standing still that long) cannot be found in the
// history kept: `complete` is then false, and the caller takes the
// whole-run path for that run. The optional area smoothing is whole-run
// only (an Error here).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "libbead/archive/measure_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/flow/flow.h"

namespace bead {

struct StreamedFlow {
  MeasureRunSummary measure;
  bool complete = true;  // false: redo the run whole (see above); the samples handed on are not the batch's
  std::string why;       // when not complete: why, in a line for the user
  std::size_t samples = 0, valid = 0;
  double total_volume_mm3 = 0.0;
  int area_outliers = 0, speed_outliers = 0, encoder_repairs = 0;
  std::vector<std::string> warnings;  // FlowResult's
};

// `opened`: OpenRun(path, pool, /*with_log=*/false). Throws bead::Error
// naming `path` when the run lacks the wheel's motion (RequireMotion's).
// `sample` gets every flow sample in profile order; `row`, when given,
// every geometry row in order.
StreamedFlow StreamRunFlow(OpenedRun opened, const std::string& path, const Rig& rig, WorkerPool& pool,
                           const MeasureRunOptions& measure, const FlowOptions& flow,
                           const std::function<void(const FlowSample&)>& sample,
                           const std::function<void(const GeometryRow&)>& row = {}, double history_s = 600.0);

// MissingMotion (open_run.h) of an opened run whose log is not read: its
// length taken from the archive.
MotionGap MissingMotionUnread(const OpenedRun& opened, const std::string& path, const std::string& needs);

// Whether StreamRunFlow takes these options (the area smoothing is
// whole-run only).
inline bool StreamableFlow(const FlowOptions& flow) { return flow.area_smooth_window <= 1; }

}  // namespace bead
