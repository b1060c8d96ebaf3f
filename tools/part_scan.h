// bead measure and bead flow on a part scan (format 1.1; the archive's
// kind = "part" chooses them): each layer against the one below; the part
// geometry CSV (part_scan.cc), or the flow along the toolpath
// (part_flow_scan.cc).
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/core/rig.h"
#include "libbead/part/measure_part.h"
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
// Shared by part_scan.cc and part_flow_scan.cc: the part rig file read,
// its warnings said; and what was measured, a line for the scan and its
// layers' words.
Rig PartRigSaying(const std::string& rig_path);
void SayMeasured(const std::string& run, const std::vector<part::LayerSummary>& layers, std::size_t total,
                 std::chrono::steady_clock::time_point start);
// A layer's pooled bead shape in words (part_shape_words.cc).
void SayShape(const part::PooledShape& s);
int FlowPartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed);

}  // namespace bead::tools
