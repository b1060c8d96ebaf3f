// Loads profiles from a run archive (.h5) or a profiles CSV (.csv).
#pragma once

#include <string>

#include "libbead/io/run_archive.h"

namespace bead::tools {

RunArchive LoadRun(const std::string& path);

// What a command that needs the wheel's motion (`needs`: "the flow",
// "explain") requires of a run: encoder readings and an acquisition log of
// at least 3 samples. Throws bead::Error naming the file and the dataset.
void RequireMotion(const RunArchive& run, const std::string& path, const std::string& needs);

}  // namespace bead::tools
