// explain's run mode with the base model identified on the run's own flow,
// and identified again where the run says the rig file misaligns it.
//
// A base model identified on flow that a stale offset misaligns has poles
// and zeros that absorbed the misalignment; held fixed through the offset
// profile (shift_profile.h) they pin the offset near the rig file's (the
// twin's stepped-wheel PRBS run, 400 points, rig file 77 counts short:
// 3020.5 +- 12 against a truth of 3071.5), or widen the interval until
// it holds the file's offset ([2965.9, 3167.4] on another seed). So where
// the run pins its offset more than half the interval's half-width from
// the one the flow is aligned at, the flow is aligned at the run's offset,
// the model identified on it again and the run explained again, until the
// offset moves by less than a quarter of its interval (at most
// kMaxRealignments times). The last model, identified where the run's best
// lies, confirms that best and narrows the interval about it (on fresh
// seeds the last interval alone missed the truth in 2 of 12 runs). So the
// offset is then profiled once more with the whole model identified again
// at every trial offset (reidentified_profile.h), and the interval printed
// holds both profiles' intervals: the run cannot say which model is right
// beyond that. The rig file's offset is called OUTSIDE only when both
// exclude it; a re-identified profile that does not cross its limit within
// its search leaves the offset not pinned.
#pragma once

#include <optional>
#include <vector>

#include "libbead/explain/base_model.h"
#include "libbead/explain/reidentified_profile.h"
#include "libbead/explain/run_explain.h"

namespace bead::explain {

inline constexpr int kMaxRealignments = 4;

struct IdentifiedRun {
  BaseModel model;                   // the last identified
  RunExplanation explanation;        // against it; its offsets in counts on the rig file's scale
  std::vector<double> realigned_at;  // the offsets the model was identified again at (empty: the rig file's)
  FlowResult flow, held_out_flow;    // the flows the last explanation read (when realigned)
  std::optional<ReidentifiedProfile> reidentified;  // where the offset was pinned by the held model's profile
};

// Throws bead::Error (naming run.path) when no model can be identified.
IdentifiedRun ExplainIdentifiedRun(const Rig& rig, const MeasuredFlow& run, const MeasuredFlow* held_out,
                                   const model::IdentifyOptions& identify, const RunExplainOptions& options);

// The base model identified on a measured flow at the explain loop's rate
// (`bin` profiles per sample).
BaseModel IdentifyOnFlow(const FlowResult& flow, std::size_t bin, const model::IdentifyOptions& identify,
                         const std::string& where);

}  // namespace bead::explain
