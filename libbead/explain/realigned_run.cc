#include "libbead/explain/realigned_run.h"

#include <algorithm>
#include <cmath>

#include "libbead/explain/reidentified_profile.h"
#include "libbead/explain/run_series.h"

namespace bead::explain {
namespace {

// The run's view with its flow computed again at another offset.
MeasuredFlow Realigned(const Rig& aligned, const MeasuredFlow& m, FlowResult& keep) {
  keep = ComputeFlow(aligned, *m.profiles, *m.geometry, *m.log, {}, m.CorrectedArea(), m.CorrectedSigma());
  MeasuredFlow out = m;
  out.flow = &keep;
  return out;
}

// Whether the run's interval excludes `counts`.
bool Excludes(const OffsetFromRun& o, double counts) {
  return o.pinned && (o.lo_counts > counts || o.hi_counts < counts);
}

// The report with its shifts `delta` counts further (from the realigned
// flow's offset to the rig file's): the profile, its interval and a kept
// shift term.
ExplainReport ShiftedBy(ExplainReport r, double delta) {
  ShiftProfile& p = r.shift_profile;
  for (double& g : p.shift_counts) g += delta;
  p.best += delta, p.lo += delta, p.hi += delta, p.first_half += delta, p.second_half += delta;
  r.position_shift_counts += delta;
  for (std::size_t k = 0; k < r.final_effects.size(); ++k)
    if (r.final_effects[k].kind == Effect::Kind::kPositionShift) r.final_params[k][0] += delta;
  return r;
}

// Whether the model should be identified again at the run's offset: the
// run pins it more than half its interval's half-width from where the flow
// is aligned. A model fitted on misaligned flow widens the interval as
// well as pulling it (a rig file 77 counts short: [2965.9, 3167.4], which
// holds the file's offset; identified again at the run's best, [3047.4,
// 3101.0], as on the same run with the file right).
bool NeedsRealigning(const OffsetFromRun& o, double aligned_at) {
  return Excludes(o, aligned_at) || (o.pinned && std::abs(o.counts - aligned_at) > 0.5 * o.ci95_counts);
}

// The interval widened to hold both profiles' (realigned_run.h): the
// model identified at the last alignment held fixed (the explain loop's
// profile, whose best stays the estimate: the corrected flow's shift term
// is its), and the model identified again at every trial offset. A
// re-identified profile that stays within its limit to the end of its
// search leaves the offset not pinned: the model's dynamics take up a
// position error as well.
void HoldBoth(RunExplanation& e, const ReidentifiedProfile& r, double rig_counts) {
  OffsetFromRun& o = e.offset;
  o.lo_counts = std::min(o.lo_counts, r.lo), o.hi_counts = std::max(o.hi_counts, r.hi);
  o.scattered = o.pinned && r.scattered;
  o.pinned = o.pinned && !r.lo_at_edge && !r.hi_at_edge;
  o.ci95_counts = o.pinned ? std::max(o.hi_counts - o.counts, o.counts - o.lo_counts) : INFINITY;
  o.excludes_rig = Excludes(o, rig_counts);
  ShiftProfile& p = e.report.shift_profile;
  p.lo = o.lo_counts - e.aligned_at_counts, p.hi = o.hi_counts - e.aligned_at_counts;
  p.lo_at_edge = p.lo_at_edge || r.lo_at_edge, p.hi_at_edge = p.hi_at_edge || r.hi_at_edge;
  e.report.position_shift_ci95_counts = o.ci95_counts;
}

}  // namespace

BaseModel IdentifyOnFlow(const FlowResult& flow, std::size_t bin, const model::IdentifyOptions& identify,
                         const std::string& where) {
  const BinnedFlow b = BinValidFlow(flow, bin);
  return IdentifyBaseModel(b.t, {b.u}, b.y, {}, identify, where);
}

IdentifiedRun ExplainIdentifiedRun(const Rig& rig, const MeasuredFlow& run, const MeasuredFlow* held_out,
                                   const model::IdentifyOptions& identify, const RunExplainOptions& options) {
  const std::size_t bin = options.profiles_per_sample ? options.profiles_per_sample : ExplainBinOf(*run.flow);
  // The corrected flow is computed once, at the end: each pass's would be
  // thrown away.
  RunExplainOptions each = options;
  each.correct_flow = false;
  IdentifiedRun out;
  out.model = IdentifyOnFlow(*run.flow, bin, identify, run.path);
  out.explanation = ExplainMeasuredRun(rig, run, held_out, out.model.tfs[0], out.model.offset, each);
  for (int k = 0; k < kMaxRealignments && NeedsRealigning(out.explanation.offset, out.explanation.aligned_at_counts);
       ++k) {
    const OffsetFromRun last = out.explanation.offset;
    Rig aligned = rig;
    aligned.offset_counts = last.counts;
    const MeasuredFlow main_view = Realigned(aligned, run, out.flow);
    MeasuredFlow other_view;
    if (held_out) other_view = Realigned(aligned, *held_out, out.held_out_flow);
    out.realigned_at.push_back(last.counts);
    out.model = IdentifyOnFlow(out.flow, bin, identify, run.path);
    out.explanation = ExplainMeasuredRun(aligned, main_view, held_out ? &other_view : nullptr, out.model.tfs[0],
                                         out.model.offset, each);
    const double moved = std::abs(out.explanation.offset.counts - last.counts);
    if (!out.explanation.offset.pinned || moved < 0.25 * out.explanation.offset.ci95_counts) break;
  }
  if (out.explanation.offset.pinned) {
    // Steps of a third of the held profile's half-width: its interval
    // crossed within a few steps on either side.
    const OffsetFromRun& o = out.explanation.offset;
    out.reidentified = ProfileReidentified(rig, run, out.model.tfs[0], o.counts, std::max(1.0, o.ci95_counts / 3.0),
                                           out.explanation.report.shift_profile.q, bin, identify);
    if (out.reidentified->ok) HoldBoth(out.explanation, *out.reidentified, rig.offset_counts);
  }
  // The corrected flow from the user's flow, as the rig file aligns it: a
  // realignment is one of the corrections it undoes (none: a shift of 0).
  if (options.correct_flow)
    out.explanation.corrected =
        CorrectFlow(rig, *run.profiles, *run.geometry, *run.log, run.CorrectedArea(), run.CorrectedSigma(),
                    ShiftedBy(out.explanation.report, out.explanation.aligned_at_counts - rig.offset_counts),
                    out.model.tfs[0], out.model.offset);
  return out;
}

}  // namespace bead::explain
