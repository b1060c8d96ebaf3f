#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/run_archive.h"

BEAD_FUZZ_READER(".h5", bead::ReadPinScanArchive(path))
