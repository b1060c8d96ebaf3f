#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"

BEAD_FUZZ_READER(".yaml", bead::ReadRigFile(path))
