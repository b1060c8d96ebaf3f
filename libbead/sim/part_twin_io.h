// The part twin's config (a simulation config whose top level holds
// `part:`) and what `bead simulate` writes for it: DIR/part.h5 (part scan),
// DIR/rig.yaml (a rig without the wheel), DIR/truth.csv (one row per
// profile: PartTruthRow's columns) and, for a layer of roads,
// DIR/truth_roads.csv (one row per road and profile: PartRoadTruth's).
#pragma once

#include <optional>
#include <string>

#include "libbead/sim/part_twin.h"

namespace bead::sim {

// The config's part: section (keys: shape (wall), seed beside it at the top
// level, and each PartTwinConfig field by name); nullopt when the file has
// no part: section (a wheel config). Unknown keys are refused at their line.
std::optional<PartTwinConfig> ReadPartTwinConfig(const std::string& path);

void WritePartTwin(const std::string& folder, const PartTwin& twin);

}  // namespace bead::sim
