#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/log_stream.h"
#include "libbead/io/run_archive.h"

// The whole-archive reader, the part scan's, and the log walked window by window as the
// streamed flow walks it (small windows, so that edges are crossed).
namespace {
void WalkLog(const std::string& path) {
  const auto log = bead::LogStream::OpenIfPresent(path, 7);
  if (!log) return;
  bead::LogWindow w;
  for (int pass = 0; pass < 2; ++pass) {
    log->Rewind();
    while (log->Next(w, pass == 1)) {
    }
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bead::fuzz::WriteInput(data, size, ".h5");
  try {
    bead::ReadRunArchive(path);
  } catch (const bead::Error&) {
  }
  try {  // a part scan (format 1.1), when its root says kind = "part"
    if (bead::IsPartScan(path)) bead::ReadPartScan(path);
  } catch (const bead::Error&) {
  }
  try {
    WalkLog(path);
  } catch (const bead::Error&) {
  }
  return 0;
}
