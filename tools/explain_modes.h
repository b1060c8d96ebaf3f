// bead explain's modes behind its options page (explain_command.cc): run
// mode (a run archive and its rig, explain_run_mode.cc), series mode (any
// CSV or .mat series, explain_series_mode.cc) and part mode (a part scan's
// flow along the path as the series, explain_part_mode.cc), with the
// printing they share (explain_print.cc).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/explain/base_model.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/realigned_run.h"
#include "libbead/explain/run_explain.h"
#include "libbead/model/identify.h"
#include "tools/series_stretches.h"

namespace bead::tools {

struct ExplainArgs {
  std::string rig, data, model, out, output, time, input_file, input_time, validate, validate_input_file, pins,
      flow_out, structure = "tf", occlusion = "pooled";
  std::vector<std::string> inputs;
  // The identified model's order: the one default, identify's (model/identify.h).
  int poles = model::IdentifyOptions{}.poles, zeros = model::IdentifyOptions{}.zeros;
  double max_delay_s = 1.0, alpha = 0.01;
  int max_effects = 5;
  std::size_t profiles_per_sample = 0;
  bool keep_off = false, no_channels = false;
  std::string series_mode = "csv";  // the JSON's mode: csv, or part (a part scan's flow as the series)
  // What the terminal and the model's source name the data and the
  // validation run by (empty: their paths; part mode reads scratch copies).
  std::string data_name, validate_name;
  std::vector<std::string> channels;

  explain::ExplainOptions Explain() const;
  const std::string& Shown(const std::string& path) const {
    const std::string& name = path == data ? data_name : path == validate ? validate_name : path;
    return name.empty() ? path : name;
  }
  SeriesNames Names() const { return {data, time, output, input_file, input_time, validate_input_file, inputs}; }
  model::IdentifyOptions Identify() const;
};

// The base model: read from --model, else identified on the data (and
// what the identification found printed).
explain::BaseModel ModelFor(const ExplainArgs& a, const std::vector<double>& t,
                            const std::vector<std::vector<double>>& u, const std::vector<double>& y,
                            const std::vector<Segment>& segments, const std::string& where);

// Run mode's model and explanation: the model file's, or one identified on
// the run's flow (and identified again where the run's offset excludes the
// rig file's: explain/realigned_run.h), said on the terminal.
explain::IdentifiedRun ExplainWithModel(const ExplainArgs& a, const Rig& rig, const explain::MeasuredFlow& run,
                                        const explain::MeasuredFlow* held_out,
                                        const explain::RunExplainOptions& options);

int ExplainRunMode(const ExplainArgs& a);
int ExplainSeriesMode(const ExplainArgs& a);
int ExplainPartMode(const ExplainArgs& a);

void PrintReport(const explain::ExplainReport& r, const std::string& unit);
void PrintRun(const explain::RunExplanation& e, const Rig& rig, const std::string& path, const std::string& validate);
void PrintPins(const explain::OffsetComparison& c, const explain::OffsetFromRun& run, const std::string& path);
void PrintCorrected(const explain::CorrectedFlow& cf, const std::string& path);
void WriteJson(const std::string& path, const nlohmann::json& j);

}  // namespace bead::tools
