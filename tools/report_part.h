// bead report on a part scan (format 1.1): the numbers its page draws.
#pragma once

#include <filesystem>
#include <string>

#include "libbead/profile/profile_processor.h"

namespace bead::tools {

// Into `dir`: part_geometry.csv and part_flow.csv (what bead measure and
// bead flow write on the scan; the flow only where it has a log),
// layers.csv (each layer in brief and its volume), sections.csv (the
// scanned surfaces of every layer at a few places along the path, in the
// bed frame) and about.csv (kind part). The rig file's warnings are said.
void WritePartReportData(const std::string& rig_path, const std::string& run, const ProfileOptions& bed,
                         const std::filesystem::path& dir);

}  // namespace bead::tools
