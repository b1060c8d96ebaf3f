// The folder of the running program (from /proc/self/exe; `fallback`'s
// folder when that cannot be read): where `bead` finds its subcommands'
// programs, and from where a subcommand finds what is installed beside it.
#pragma once

#include <limits.h>
#include <unistd.h>

#include <string>

namespace bead::tools {

inline std::string OwnFolder(const char* fallback) {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  const std::string self = n > 0 ? std::string(path, static_cast<std::size_t>(n)) : std::string(fallback);
  const auto slash = self.rfind('/');
  return slash == std::string::npos ? "." : self.substr(0, slash);
}

}  // namespace bead::tools
