// Printing an identified model as `bead identify` shows it: the transfer
// function(s), process form, operating point, the delay's basins.
#pragma once

#include <string>
#include <vector>

#include "libbead/model/identify.h"
#include "libbead/model/identify_multi.h"

namespace bead::tools {

void PrintModel(const model::IdentifiedModel& m, const model::IdentifyOptions& o);
void PrintMultiInputModel(const model::MultiInputModel& m, const std::vector<model::IdentifyOptions>& o,
                          const std::vector<std::string>& inputs);

}  // namespace bead::tools
