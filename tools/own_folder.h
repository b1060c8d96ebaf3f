// The folder of the running program (from /proc/self/exe; `fallback`'s
// folder when that cannot be read): where `bead` finds its subcommands'
// programs, and from where a subcommand finds what is installed beside it.
#pragma once

#include <limits.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace bead::tools {

inline std::string OwnFolder(const char* fallback) {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  const std::string self = n > 0 ? std::string(path, static_cast<std::size_t>(n)) : std::string(fallback);
  const auto slash = self.rfind('/');
  return slash == std::string::npos ? "." : self.substr(0, slash);
}

// What `cmake --install` puts in PREFIX/share/bead (`relative` there,
// beside PREFIX/bin of this program), else `source_path` in the source tree
// the program was built from.
inline std::string InstalledOr(const std::string& relative, const std::string& source_path) {
  const std::filesystem::path installed =
      std::filesystem::path(OwnFolder("")).parent_path() / "share" / "bead" / relative;
  return std::filesystem::exists(installed) ? installed.string() : source_path;
}

}  // namespace bead::tools
