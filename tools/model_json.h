// The model file of `bead identify -o` and `bead explain --model`: JSON with
// num, den (descending powers of s) and delay_s (version 1), and since
// version 2 the operating point ({offset, input_level, output_level}: y =
// offset + G(s) u), the structure, the process form, the fit, the delay
// profile and what was left out of the fit. A file without an operating
// point is read with offset 0.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"

namespace bead::tools {

struct ModelFile {
  model::TransferFunction tf;
  double offset = 0.0;
  bool has_operating_point = false;
};

ModelFile ReadModelFile(const std::string& path);

// The identified model as JSON (input and output name the columns).
nlohmann::json ModelJson(const model::IdentifiedModel& m, const model::IdentifyOptions& o, const std::string& input,
                         const std::string& output, const std::vector<double>& t, const std::vector<Segment>& segments,
                         const std::vector<Exclusion>& excluded);

// Prints the model, its operating point, the delay's basins and what was
// left out, as `bead identify` and `bead explain` show them.
void PrintModel(const model::IdentifiedModel& m, const model::IdentifyOptions& o);

}  // namespace bead::tools
