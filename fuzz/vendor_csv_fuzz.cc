// The columns of the bead-observer export (testdata/realdata), z as distance.
#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/vendor_csv.h"

namespace {
bead::ImportColumns Columns() {
  bead::ImportColumns c;
  c.profile = "ScanID";
  c.time = "Timestamp";
  c.x = "X";
  c.z = "Z";
  c.z_is_distance = true;
  return c;
}
}  // namespace

BEAD_FUZZ_READER(".csv", bead::ReadVendorCsv(path, Columns()))
