// The series CSV of `bead identify` and `bead explain` (columns t, u, y).
#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "tools/csv_columns.h"

BEAD_FUZZ_READER(".csv", bead::tools::ReadSeries({path, "t", "u", "y", "", ""}))
