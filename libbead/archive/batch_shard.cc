#include "libbead/archive/batch_shard.h"

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace bead {
namespace {

double FileBytes(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0.0 : static_cast<double>(size);
}

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<std::size_t> ShardRuns(const std::vector<BatchRun>& runs, const Shard& shard) {
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (shard.Takes(i)) mine.push_back(i);
  return mine;
}

ShardTally RunShard(const std::vector<BatchRun>& runs, const BatchOptions& options, const Shard& shard,
                    WorkerPool& pool, bool redo, const BatchEvents& events) {
  const std::vector<std::size_t> mine = ShardRuns(runs, shard);
  ShardTally tally;
  tally.runs = mine.size();
  double total_bytes = 0, done_bytes = 0;
  for (std::size_t i : mine) total_bytes += FileBytes(runs[i].run);
  std::size_t profiles_done = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const BatchRun& run = runs[mine[k]];
    const double bytes = FileBytes(run.run);
    if (!redo && RunComplete(run, options)) {
      ++tally.skipped;
      total_bytes -= bytes;
      if (events.skipped) events.skipped(k, mine.size(), run);
      continue;
    }
    auto progress = [&](std::size_t done, std::size_t total) {
      if (!events.progress) return;
      const double elapsed = Since(start);
      const double now =
          done_bytes + bytes * static_cast<double>(done) / static_cast<double>(std::max<std::size_t>(total, 1));
      const double rate = elapsed > 0 ? static_cast<double>(profiles_done + done) / elapsed : 0;
      events.progress(k, mine.size(), run, done, total, rate, now > 0 ? elapsed * (total_bytes - now) / now : -1);
    };
    const auto t0 = std::chrono::steady_clock::now();
    const RunResult r = ProcessRun(run, options, pool, progress);
    done_bytes += bytes;
    profiles_done += r.profiles;
    ++tally.processed;
    tally.failed += !r.ok();
    if (events.finished) events.finished(k, mine.size(), run, r, Since(t0));
  }
  tally.summary = WriteSummary(runs, options);
  return tally;
}

}  // namespace bead
