// The occlusion stage as the commands run it: --occlusion pooled (default:
// one shape for the run, fitted on a few dozen profiles), each (a fit per
// profile: slower), or none. Prints a one-line summary.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/io/run_archive.h"
#include "libbead/profile/bead_geometry.h"

namespace bead::tools {

struct OcclusionColumns {
  std::vector<double> corrected, bias, sigma;  // NaN where not available
};

void AddOcclusionOption(CLI::App* cmd, std::string& mode);

OcclusionColumns RunOcclusion(const std::string& mode, const Rig& rig, const ProfileBlock& block,
                              const std::vector<BeadGeometry>& geometry);

}  // namespace bead::tools
