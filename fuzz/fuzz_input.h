// libFuzzer targets for the readers of outside input. Each target writes the
// fuzzer's bytes to a file (the readers take paths, as users give them) and
// reads it. A reader may refuse the file only with bead::Error (one line
// naming the file and the place); anything else escaping it (another
// exception, a crash, a sanitizer report) is a bug the fuzzer reports.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace bead::fuzz {

// The input as a file of this process (reused from one input to the next).
inline std::string WriteInput(const uint8_t* data, size_t size, const char* extension) {
  static const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path = dir + "/bead_fuzz_" + std::to_string(getpid()) + extension;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  if (size && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

}  // namespace bead::fuzz

// Every target's body: `call` reads the file at `path`.
#define BEAD_FUZZ_READER(extension, call)                                   \
  extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) { \
    const std::string path = bead::fuzz::WriteInput(data, size, extension); \
    try {                                                                   \
      call;                                                                 \
    } catch (const bead::Error&) {                                          \
    }                                                                       \
    return 0;                                                               \
  }
