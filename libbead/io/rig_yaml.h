// Rig file (YAML) of docs/data-formats.md. The reader names the
// file, the line and the key of anything missing or wrong. Keys the spec
// does not list are kept in `document`, so rewriting a rig file (a new
// offset from calibration) loses nothing the user had.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "libbead/core/rig.h"

namespace bead {

struct RigFile {
  Rig rig;
  YAML::Node document;              // the whole file as read
  bool has_reference_areas = true;  // false: absent, and not required
  // Keys one edit away from a listed one, each "file:line N: key: ... did
  // you mean ...?" (io/rig_keys.h); the caller says them.
  std::vector<std::string> warnings;
};

// areas_required = false: a file without sensor.reference_areas_mm is read
// (bead calibrate reference proposes them); when present they are checked.
RigFile ReadRigFile(const std::string& path, bool areas_required = true);
// The rig alone; its key warnings appended to `warnings` when given.
inline Rig ReadRig(const std::string& path, std::vector<std::string>* warnings = nullptr) {
  RigFile f = ReadRigFile(path);
  if (warnings) warnings->insert(warnings->end(), f.warnings.begin(), f.warnings.end());
  return f.rig;
}
// The rig of a part scan (format 1.1): the wheel's sections may be left
// out (rig.has_wheel = false); the reference areas (bare bed either side of
// the first layer) are required.
RigFile ReadPartRigFile(const std::string& path);
// Parses YAML text; `name` is used in errors in place of a file name.
// wheel_required = false: a rig without encoder, wheel and offset is read.
RigFile ParseRig(const std::string& text, const std::string& name, bool areas_required = true,
                 bool wheel_required = true);

// Writes `file.document` with the spec keys set from `file.rig`, atomically.
void WriteRigFile(const std::string& path, const RigFile& file);
// A fresh document for a rig (no keys of its own).
RigFile MakeRigFile(const Rig& rig);

}  // namespace bead
