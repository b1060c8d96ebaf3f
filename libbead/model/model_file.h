// The model file of `bead identify -o` and `bead explain --model`
// (docs/data-formats.md, "Model file"): JSON with num, den (descending
// powers of s) and delay_s (version 1); since version 2 the operating point
// ({offset, input_level, output_level}: y = offset + G(s) u), the
// structure, the process form, the fit, the delay profile and what was left
// out of the fit; version 3, a model with several inputs: `inputs`, one
// entry per input with its own num, den, delay_s and the rest, and one
// operating point (y = offset + sum_i G_i(s) u_i). A file without an
// operating point is read with offset 0.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libbead/core/segment.h"
#include "libbead/model/identify.h"
#include "libbead/model/identify_multi.h"
#include "libbead/series/process_on.h"

namespace bead::model {

struct ModelFile {
  std::vector<std::string> inputs;    // the input columns the model was identified from ("" where not recorded)
  std::vector<TransferFunction> tfs;  // one per input, in that order
  std::string output;
  double offset = 0.0;
  bool has_operating_point = false;
};

// Throws bead::Error naming the file and the key when it is not a model.
ModelFile ReadModelFile(const std::string& path);

// What a JSON file is, by its content: "model" (num and den, or inputs),
// "explain" (an explain report), "" (neither); and the same in words for a
// message ("an explain report (bead explain -o)").
std::string JsonKind(const nlohmann::json& j);
std::string DescribeJsonKind(const nlohmann::json& j);

// The identified model as JSON (input and output name the columns).
nlohmann::json ModelJson(const IdentifiedModel& m, const IdentifyOptions& o, const std::string& input,
                         const std::string& output, const std::vector<double>& t, const std::vector<Segment>& segments,
                         const std::vector<Exclusion>& excluded);
nlohmann::json MultiInputModelJson(const MultiInputModel& m, const std::vector<IdentifyOptions>& o,
                                   const std::vector<std::string>& inputs, const std::string& output,
                                   const std::vector<double>& t, const std::vector<Segment>& segments,
                                   const std::vector<Exclusion>& excluded);

// A polynomial in s as text, "1.2 s^2 + 3 s + 4".
std::string PolynomialText(const std::vector<double>& c);

}  // namespace bead::model
