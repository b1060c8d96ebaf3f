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

// A rig file for command-line tests: the spec's example rig, the reference
// areas either side of the bead at [-24, -12] and [12, 24] mm.
inline const char* const kCliRigYaml =
    "encoder: {counts_per_rev: 4096, bits: 32, direction: 1}\n"
    "wheel: {diameter_mm: 254.762}\noffset: {counts: 3000}\n"
    "sensor: {reference_areas_mm: [[-24, -12], [12, 24]]}\n";

inline std::pair<int, std::string> RunCli(const TempDir& dir, const std::string& args) {
  const std::string cmd = std::string(BEAD_CLI) + " " + args + " >" + (dir / "out.txt") + " 2>&1";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadText(dir / "out.txt")};
}

// How many times `what` occurs in `text` (what a command printed or wrote).
inline int Occurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace bead::test
