// Vendor CSV exports of laser line profilers: one row per point, the
// columns named as the vendor names them and in any order (a mapping says
// which is which; the others are ignored), z either as height or as the
// distance from the sensor. Read into a run archive of
// docs/data-formats.md; an export without an encoder column gets
// encoder 0 and the root attribute encoder = "absent" (run_archive.h), so
// what needs the wheel's motion can refuse it instead of reading a
// standstill.
#pragma once

#include <cstddef>
#include <string>

#include "libbead/io/run_archive.h"

namespace bead {

struct VendorCsvColumns {
  std::string profile;  // whole-number profile id; a profile's rows together
  std::string time;     // profile time (a profile takes its first row's)
  std::string x;        // across the laser line
  std::string z;        // height, or distance from the sensor (z_is_distance)
  std::string encoder;  // empty: the export has none
  double time_scale = 1.0;     // the time column times this is seconds
  bool z_is_distance = false;  // z grows away from the sensor: height = -z
};

struct VendorImport {
  RunArchive run;
  std::size_t rows = 0;  // points read
};

// Throws bead::Error naming the file, the line and the column.
VendorImport ReadVendorCsv(const std::string& path, const VendorCsvColumns& columns);

}  // namespace bead
