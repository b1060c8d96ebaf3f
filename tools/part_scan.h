// bead measure and bead flow on a part scan (format 1.1; the archive's
// kind = "part" chooses them): each layer against the one below; the part
// geometry CSV, or the flow along the toolpath.
#pragma once

#include <string>

#include "libbead/profile/profile_processor.h"

namespace bead::tools {

int MeasurePartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                    const ProfileOptions& bed, unsigned threads);
int FlowPartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed);

}  // namespace bead::tools
