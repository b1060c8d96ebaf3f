#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"

// The rig file as the wheel's commands read it, and as a part scan's
// (format 1.1: the part: section, the wheel's sections optional).
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bead::fuzz::WriteInput(data, size, ".yaml");
  try {
    bead::ReadRigFile(path);
  } catch (const bead::Error&) {
  }
  try {
    bead::ReadPartRigFile(path);
  } catch (const bead::Error&) {
  }
  return 0;
}
