// A scratch folder under /tmp for a command's intermediate files, removed
// with what it holds when the command is done (or fails).
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "libbead/core/error.h"

namespace bead::tools {

struct ScratchFolder {
  std::filesystem::path dir;
  // `what`: the files it is for, said if it cannot be made.
  explicit ScratchFolder(const std::string& what) {
    char tmpl[] = "/tmp/bead-XXXXXX";
    if (!mkdtemp(tmpl)) throw Error("cannot make a scratch folder in /tmp for " + what);
    dir = tmpl;
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace bead::tools
