#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/sim/part_twin_io.h"
#include "libbead/sim/sim_config.h"

// The wheel's simulation config, and the part twin's (a part: section).
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bead::fuzz::WriteInput(data, size, ".yaml");
  try {
    bead::sim::ReadSimConfig(path);
  } catch (const bead::Error&) {
  }
  try {
    bead::sim::ReadPartTwinConfig(path);
  } catch (const bead::Error&) {
  }
  return 0;
}
