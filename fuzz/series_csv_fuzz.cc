// The series CSV of `bead identify` and `bead explain` (columns t, u, y).
#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/series_columns.h"

BEAD_FUZZ_READER(".csv", bead::ReadSeries({path, "t", "u", "y", "", ""}))
