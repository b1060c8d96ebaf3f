// What `bead import` reads from a file made by another tool: which of its
// columns (CSV), variables (.mat) or fields (PLY/PCD) hold the profile's
// number, its time, x, z and the wheel encoder, and how to turn them into
// the run archive's units. The readers (vendor_csv.h, mat_run.h,
// point_cloud.h) all fill an ImportedRun.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

#include "libbead/io/run_archive.h"

namespace bead {

struct ImportColumns {
  std::string profile;         // whole-number profile id (CSV), the field ordering the scan lines (PLY/PCD)
  std::string time;            // profile time (a profile takes its first point's)
  std::string x;               // across the laser line
  std::string z;               // height, or distance from the sensor (z_is_distance)
  std::string encoder;         // empty: the file has none
  double time_scale = 1.0;     // the time column times this is seconds
  bool z_is_distance = false;  // z grows away from the sensor: height = -z
  // A part scan (format 1.1; vendor CSV): each profile's layer, and its
  // place along the toolpath (path, mm) or the head's speed to place it
  // (path = speed x time from the layer's first profile); the frame's
  // height above the bed and lateral offset when the file has them.
  std::string layer;             // non-empty: the file is a part scan
  std::string path;              // mm along the toolpath
  double head_speed_mm_s = 0.0;  // > 0 and no path column: path = speed x time in the layer
  std::string frame_z;           // mm; 0 when not named
  std::string frame_x;           // mm; 0 when not named
  bool part() const { return !layer.empty(); }
};

// The wheel's columns by name (a part's stay empty), for code that names
// them all in one line.
inline ImportColumns Columns(std::string profile, std::string time, std::string x, std::string z, std::string encoder,
                             double time_scale, bool z_is_distance) {
  ImportColumns c;
  c.profile = std::move(profile), c.time = std::move(time), c.x = std::move(x), c.z = std::move(z);
  c.encoder = std::move(encoder), c.time_scale = time_scale, c.z_is_distance = z_is_distance;
  return c;
}

struct ImportedRun {
  RunArchive run;
  std::size_t rows = 0;  // points read
};

// Checks what every reader needs of `c` (a positive time scale, the time,
// x and z named; the profile too when `profile_required`); throws
// bead::Error naming `path`.
// A part scan's columns: a path column or a head speed, not both.
void CheckImportColumns(const std::string& path, const ImportColumns& c, bool profile_required);

}  // namespace bead
