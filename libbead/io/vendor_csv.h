// Vendor CSV exports of laser line profilers: one row per point, the
// columns named as the vendor names them and in any order (a mapping says
// which is which; the others are ignored), z either as height or as the
// distance from the sensor. Read into a run archive of
// docs/data-formats.md; an export without an encoder column gets
// encoder 0 and the root attribute encoder = "absent" (run_archive.h), so
// what needs the wheel's motion can refuse it instead of reading a
// standstill.
#pragma once

#include <string>

#include "libbead/io/import_columns.h"

namespace bead {

// Throws bead::Error naming the file, the line and the column.
ImportedRun ReadVendorCsv(const std::string& path, const ImportColumns& columns);

}  // namespace bead
