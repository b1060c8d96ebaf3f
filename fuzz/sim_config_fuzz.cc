#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/sim/sim_config.h"

BEAD_FUZZ_READER(".yaml", bead::sim::ReadSimConfig(path))
