#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/profiles_csv.h"

// Both log forms read the same bytes: the wheel run's and the part scan's.
BEAD_FUZZ_READER(".csv", {
  try {
    bead::ReadLogCsv(path);
  } catch (const bead::Error&) {
  }
  bead::ReadPartLogCsv(path);
})
