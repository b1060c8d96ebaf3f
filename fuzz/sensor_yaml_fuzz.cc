#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/vision/sensor_yaml.h"

BEAD_FUZZ_READER(".yaml", bead::vision::ReadSensorYaml(path))
