// OpenRun: a run ready to stream, from a run archive (.h5: the log and
// root attributes read now, the profiles window by window) or a profiles
// CSV (.csv: read whole, no log).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "libbead/core/worker_pool.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"

namespace bead {

struct OpenedRun {
  RunArchive run;  // log and attributes; run.profiles stays empty
  std::unique_ptr<ProfileStream> profiles;
  bool archive = false;  // an HDF5 run archive (a CSV has no log)
};

// `pool` decompresses the archive's chunks; it must outlive the stream.
// with_log = false: the log is not read (bead measure needs none).
OpenedRun OpenRun(const std::string& path, WorkerPool& pool, bool with_log = true);

// What a stage that needs the wheel's motion (`needs`: "the flow",
// "explain") lacks in a run: encoder readings, an acquisition log, one of
// at least 3 samples. `dataset` names where; empty `why` when nothing.
struct MotionGap {
  std::string dataset, why;
  bool none() const { return why.empty(); }
};
MotionGap MissingMotion(const RunArchive& run, const std::string& needs);
// The same from what is known without reading the log: its length
// (nullopt: the run has none).
MotionGap MissingMotion(bool encoder_absent, std::optional<std::size_t> log_samples, const std::string& needs);
// Throws bead::Error naming `path` and the dataset when something lacks.
void RequireMotion(const RunArchive& run, const std::string& path, const std::string& needs);

}  // namespace bead
