#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/profiles_csv.h"

BEAD_FUZZ_READER(".csv", bead::ReadProfilesCsv(path))
