// The base model explain holds the data against: read from a model file
// (bead identify -o), or identified on the data itself (one transfer
// function per input, operating point and initial state estimated).
#pragma once

#include <string>
#include <vector>

#include "libbead/core/run_data.h"
#include "libbead/model/identify.h"
#include "libbead/model/transfer_function.h"

namespace bead::explain {

struct BaseModel {
  std::vector<std::string> inputs;  // a model file's input names (empty when identified)
  std::vector<model::TransferFunction> tfs;
  double offset = 0.0;
  std::string source;  // where it came from, in words
  // When identified on the data: its fit, and what the identification warned of.
  bool identified = false;
  double fit_percent = 0.0;
  std::vector<std::string> warnings;
};

// A model file's, refused (bead::Error naming the file) when its number of
// inputs is not `inputs`.
BaseModel BaseModelFromFile(const std::string& path, std::size_t inputs);

// Identified on t, u (one series per input), y over `segments`; `where`
// names the data in the errors and the source. Throws bead::Error when no
// model can be identified.
BaseModel IdentifyBaseModel(const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                            const std::vector<double>& y, const std::vector<Segment>& segments,
                            const model::IdentifyOptions& options, const std::string& where);

}  // namespace bead::explain
