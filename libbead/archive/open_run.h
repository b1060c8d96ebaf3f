// OpenRun: a run ready to stream, from a run archive (.h5: the log and
// root attributes read now, the profiles window by window) or a profiles
// CSV (.csv: read whole, no log).
#pragma once

#include <memory>
#include <string>

#include "libbead/core/worker_pool.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"

namespace bead {

struct OpenedRun {
  RunArchive run;  // log and attributes; run.profiles stays empty
  std::unique_ptr<ProfileStream> profiles;
};

// `pool` decompresses the archive's chunks; it must outlive the stream.
OpenedRun OpenRun(const std::string& path, WorkerPool& pool);

}  // namespace bead
