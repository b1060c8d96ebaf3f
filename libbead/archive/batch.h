// The batch: every run of a list measured and its flow computed, into
//   OUT/<name>/geometry.csv   the geometry CSV (as bead measure writes it)
//   OUT/<name>/flow.csv       the flow CSV (as bead flow; runs with a log)
//   OUT/<name>/inputs.txt     what the results were made from
//   OUT/<name>/result.csv     the run's summary row, written last
//   OUT/summary.csv           a row per run, rebuilt from the result.csv files
// Every file is written atomically, result.csv after the others: a run is
// complete when its result.csv says ok and its inputs.txt matches the
// inputs now (the files' sizes and times, the rig's text, the options).
// A batch killed at any moment and started again redoes only the runs not
// complete, and its files equal an uninterrupted batch's byte for byte
// (nothing in them depends on time, threads or shard).
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "libbead/archive/batch_runs.h"
#include "libbead/archive/measure_run.h"
#include "libbead/core/worker_pool.h"
#include "libbead/flow/flow.h"

namespace bead {

struct BatchOptions {
  std::string out;  // output folder (created)
  ProfileOptions profile;
  FlowOptions flow;
  OcclusionMode occlusion = OcclusionMode::kPooled;
  occlusion::Estimator estimate = nullptr;  // as MeasureRunOptions::estimate
};

struct RunResult {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string name, run, rig;
  std::string status = "ok";  // or "failed: why"
  std::size_t profiles = 0, valid = 0, flow_samples = 0;
  double total_volume_mm3 = kNaN;    // empty when the run has no flow
  double offset_counts = kNaN;       // the rig's nozzle-to-laser offset used
  double occlusion_fraction = kNaN;  // pooled hidden fraction of the area
  std::vector<std::string> warnings;
  bool ok() const { return status == "ok"; }
};

std::string RunFolder(const BatchOptions& options, const BatchRun& run);
bool RunComplete(const BatchRun& run, const BatchOptions& options);

// Measures one run and writes its files. Never throws for the run's own
// faults: a run that cannot be processed comes back with status "failed: ...".
// progress: (profiles measured, profiles in the run).
RunResult ProcessRun(const BatchRun& run, const BatchOptions& options, WorkerPool& pool,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});

struct SummaryState {
  std::size_t complete = 0, failed = 0;
  std::vector<std::string> missing;  // names of runs with no result yet
};

// Rebuilds OUT/summary.csv from the result.csv of `runs` (in their order),
// under a lock on OUT/.summary.lock, so that of shards finishing together
// the last to write saw every run the others finished.
SummaryState WriteSummary(const std::vector<BatchRun>& runs, const BatchOptions& options);

}  // namespace bead
