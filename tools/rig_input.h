// A rig file read by a command: its key warnings (a key one edit away from
// a listed one, io/rig_keys.h) said on stderr before any work.
#pragma once

#include <cstdio>
#include <string>

#include "libbead/io/rig_yaml.h"

namespace bead::tools {

inline void SayRigWarnings(const RigFile& file) {
  for (const std::string& w : file.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

inline RigFile ReadRigFileSaying(const std::string& path, bool areas_required = true) {
  RigFile file = ReadRigFile(path, areas_required);
  SayRigWarnings(file);
  return file;
}

inline Rig ReadRigSaying(const std::string& path) { return ReadRigFileSaying(path).rig; }

}  // namespace bead::tools
