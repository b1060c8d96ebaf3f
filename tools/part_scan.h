// bead measure and bead flow on a part scan (format 1.1; the archive's
// kind = "part" chooses them): each layer against the one below; the part
// geometry CSV, or the flow along the toolpath.
#pragma once

#include <string>

#include "libbead/core/error.h"
#include "libbead/profile/profile_processor.h"

namespace bead::tools {

int MeasurePartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                    const ProfileOptions& bed, unsigned threads);
// bead measure --beads all: each bead of every profile (part/roads.h), the
// spec's one row per bead; a part scan layer on layer, a run's profiles
// each on the bed.
int MeasureRoads(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed, bool laid_left_first, unsigned threads);
// Why a part scan has no flow: its file has no nozzle log (a part profiles
// CSV never has one).
Error NoNozzleLog(const std::string& run);
int FlowPartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed);

}  // namespace bead::tools
