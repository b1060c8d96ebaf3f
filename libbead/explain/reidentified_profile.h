// The profile over the encoder offset with the whole base model (poles,
// zeros, delay, gain, operating point, initial state) identified again at
// every trial offset: the flow computed again at the trial's alignment, the
// model refined from its neighbour's (a warm start, model::IdentifyOptions::
// start: one basin, so that identify's own delay basins do not scatter the
// profile). A model identified on flow one alignment gives absorbs that
// alignment in its poles and zeros; held fixed through the profile
// (shift_profile.h) it favours the offset it was fitted at. Here no
// alignment's model is favoured: each has its own.
//
// The interval is where the SSE stays within SSE_min + chi2_1(0.95) q, q the
// residual's long-run variance along the offset from the explain loop's
// shift profile (shift_profile.h), as there.
#pragma once

#include <cstddef>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/explain/run_explain.h"
#include "libbead/model/identify.h"

namespace bead::explain {

struct ReidentifiedProfile {
  std::vector<double> counts, sse;  // the trial offsets (rig file's scale) and their SSE, increasing in counts
  double best = NAN, lo = NAN, hi = NAN;
  // The SSE stayed below the limit to the search's end, or the trial past
  // the band identified no model.
  bool lo_at_edge = false, hi_at_edge = false;
  bool ok = false;  // at least three trials identified
  // The SSE falls and rises again on one side of its least: identify's
  // basins, not the data, shaped it; not pinned (both sides at the edge).
  bool scattered = false;
};

// About `centre` (counts) in steps of `step` counts, out to where the SSE
// crosses its limit on each side (at most kMaxReidSteps steps), starting
// from `start` (the model identified at `centre`); `bin` profiles per
// sample, as the explain loop's.
inline constexpr int kMaxReidSteps = 12;
ReidentifiedProfile ProfileReidentified(const Rig& rig, const MeasuredFlow& run, const model::TransferFunction& start,
                                        double centre, double step, double q, std::size_t bin,
                                        const model::IdentifyOptions& identify);

}  // namespace bead::explain
