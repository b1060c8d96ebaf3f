#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/model/model_file.h"

BEAD_FUZZ_READER(".json", bead::model::ReadModelFile(path))
