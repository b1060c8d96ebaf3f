// Loads profiles from a run archive (.h5) or a profiles CSV (.csv).
#pragma once

#include <string>

#include "libbead/io/run_archive.h"

namespace bead::tools {

RunArchive LoadRun(const std::string& path);

}  // namespace bead::tools
