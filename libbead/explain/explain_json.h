// explain's report as JSON (explain.json): the loop's answers with their
// intervals, the diagnostics, and in run mode the offset from the run, the
// pin scans beside it and the corrected flow. The layout is docs'.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/reidentified_profile.h"
#include "libbead/explain/run_explain.h"
#include "libbead/model/transfer_function.h"

namespace bead::explain {

// A base model's input after the first, for the report.
struct NamedModel {
  std::string input;
  model::TransferFunction tf;
};

// The loop's report and the model it started from (any mode; `more`: the
// base model's other inputs, as model.more_inputs).
nlohmann::json ReportJson(const ExplainReport& r, const model::TransferFunction& tf, double offset,
                          const std::string& model_source, const std::vector<NamedModel>& more = {});

// Run mode: ReportJson's fields and the offset, the time stamps, the pins
// (when compared) and the corrected flow (when computed; `flow_out` the
// path it was or would have been written to).
nlohmann::json RunJson(const RunExplanation& e, const Rig& rig, const model::TransferFunction& tf, double offset,
                       const std::string& model_source, const std::optional<OffsetComparison>& pins,
                       const std::string& flow_out);

// The offset's profile with the model identified again at every trial
// offset (reidentified_profile.h): {offset_counts, sse, best_counts,
// ci95_low_counts, ci95_high_counts, low_at_search_edge, high_at_search_edge}.
nlohmann::json ReidentifiedJson(const ReidentifiedProfile& r);

// The measured output and the model's, alone and with the effects kept,
// at every sample of `d` (every k-th where there are more than
// `max_points`), as compare: {t_s, measured, model_before, model_after,
// unit}: the report's compare plot.
nlohmann::json CompareJson(const SeriesData& d, const ExplainReport& r, std::size_t max_points = 4000);

// A number, or null where it is not finite (an unpinned interval).
nlohmann::json Finite(double v);

}  // namespace bead::explain
