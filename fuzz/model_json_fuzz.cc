#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "tools/model_json.h"

BEAD_FUZZ_READER(".json", bead::tools::ReadModelFile(path))
