// Progress of a long step, on a terminal only: "\r<what> N / M profiles"
// on stderr while it works, the line cleared when done (a pipe or a log
// file gets nothing of it).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>

namespace bead::tools {

// The callback to hand a MeasureRunOptions::progress (or any step that
// counts `unit`s: "\r<what> N / M <unit>"); empty off a terminal.
inline std::function<void(std::size_t, std::size_t)> TtyProgress(const std::string& what,
                                                                 const std::string& unit = "profiles") {
  if (!isatty(STDERR_FILENO)) return {};
  return [what, unit](std::size_t done, std::size_t total) {
    std::fprintf(stderr, "\r%s %zu / %zu %s", what.c_str(), done, total, unit.c_str());
    if (done >= total) std::fprintf(stderr, "\r\033[K");
  };
}

}  // namespace bead::tools
