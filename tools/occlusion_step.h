// The occlusion stage as the commands run it: --occlusion pooled (default:
// one shape for the run, fitted on a few dozen profiles), each (a fit per
// profile: slower), or none (libbead/archive/measure_run.h runs it).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace bead::tools {

void AddOcclusionOption(CLI::App* cmd, std::string& mode);

}  // namespace bead::tools
