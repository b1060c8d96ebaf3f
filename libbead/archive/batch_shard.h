// RunShard: one process's share of a batch (batch_runs.h's Shard): each of
// its runs processed (ProcessRun) unless its results are complete, the
// summary rebuilt at the end. What happens is told through BatchEvents,
// for the command to print; the estimate of the time left weighs the runs
// by their files' sizes.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "libbead/archive/batch.h"
#include "libbead/archive/batch_runs.h"
#include "libbead/core/worker_pool.h"

namespace bead {

struct BatchEvents {
  // `k` counts from 0 among the shard's `of` runs.
  std::function<void(std::size_t k, std::size_t of, const BatchRun& run)> skipped;
  // Within a run: profiles measured of the run's, the batch's rate so far
  // (profiles/s) and the time left (s; negative: not known yet).
  std::function<void(std::size_t k, std::size_t of, const BatchRun& run, std::size_t done, std::size_t total,
                     double rate, double left_s)>
      progress;
  std::function<void(std::size_t k, std::size_t of, const BatchRun& run, const RunResult& result, double seconds)>
      finished;
};

struct ShardTally {
  std::size_t runs = 0, processed = 0, skipped = 0, failed = 0;
  SummaryState summary;  // after the rebuild
};

// The indices of `runs` the shard takes.
std::vector<std::size_t> ShardRuns(const std::vector<BatchRun>& runs, const Shard& shard);

// redo: process runs whose results are complete too.
ShardTally RunShard(const std::vector<BatchRun>& runs, const BatchOptions& options, const Shard& shard,
                    WorkerPool& pool, bool redo, const BatchEvents& events);

}  // namespace bead
