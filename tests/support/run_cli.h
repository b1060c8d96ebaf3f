// Runs the `bead` command line (BEAD_CLI, set by tests/CMakeLists.txt) with
// `args`, its output and errors into DIR/out.txt: the exit status (-1 when
// it did not exit, e.g. killed by a signal) and that text.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <utility>

#include "tests/support/temp_dir.h"

namespace bead::test {

inline std::pair<int, std::string> RunCli(const TempDir& dir, const std::string& args) {
  const std::string cmd = std::string(BEAD_CLI) + " " + args + " >" + (dir / "out.txt") + " 2>&1";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadText(dir / "out.txt")};
}

}  // namespace bead::test
