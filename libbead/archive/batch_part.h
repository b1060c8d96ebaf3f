// bead batch on a part scan (format 1.1: kind = "part"): each layer
// measured against the one below (part/measure_part.h), the part geometry
// CSV, and the flow along the toolpath where the scan has its log.
#pragma once

#include <string>

#include "libbead/archive/batch.h"

namespace bead {

// Writes DIR/geometry.csv and DIR/flow.csv (the part forms) and fills r's
// counts: profiles, valid, flow_samples, total_volume_mm3 (the layers'
// volumes summed), occlusion_fraction (the groove hidden under the
// overhangs over the area seen, over the corrected rows). Throws on the
// scan's or the rig's faults (the caller turns them into the run's status).
void ProcessPartScan(const BatchRun& job, const std::string& dir, const BatchOptions& options, RunResult& r);

}  // namespace bead
