// The fit against the wheel-position shift (the encoder offset the run
// itself implies): at each shift of a grid over the searched range every
// other term (the base model's gain, operating point, initial state and
// delay, the effects kept) refitted, continuing from the neighbour. The
// interval is where the SSE stays within SSE_min + chi2_1(0.95) q, q the
// long-run variance the residual has along the profiled direction
// (parameter_covariance.h, long_run.h): a smooth residual's q is many times
// its variance, so an interval a white-noise rule would make +-0.1 count
// wide widens to what the data allow. The minimum is refined between grid
// points by a parabola through the three lowest (the rig file's value sits
// on the grid, and a best shift snapped to it would be the rig file's by
// construction).
#pragma once

#include <cmath>
#include <vector>

#include "libbead/explain/effect_fit.h"

namespace bead::explain {

struct ShiftProfile {
  std::vector<double> shift_counts, sse;
  double best = 0.0, lo = 0.0, hi = 0.0;        // 95 % interval [lo, hi]
  bool lo_at_edge = false, hi_at_edge = false;  // the interval reaches the searched range there
  double q = 0.0;                               // the threshold's scale (ShiftInterval)
  double s_min = 0.0;                           // the SSE at the refined best
  EffectSet refit_at_best;                      // every other term as refitted at the best grid shift
  std::size_t best_index = 0;                   // the lowest grid shift
  double curvature = 0.0;  // SSE = s_min + curvature (s - best)^2 through the lowest three; 0: no parabola
  // The split-half check (confounding.h): the best shift on each half of
  // the run, and whether they differ by more than the interval allows.
  double first_half = NAN, second_half = NAN;
  bool halves_disagree = false;
  // The offset trades with the delay beyond what the run can separate
  // (confounding.h): not pinned whatever the profile's curvature.
  bool inseparable = false;
  // The offset-delay correlation the wheel's speed changes allow, from the
  // speed and the model's output alone (speed_follows_input.h).
  double speed_delay_correlation = NAN;
  bool steady_wheel = false;  // that correlation beyond its bar: not pinned
  // The share of the wheel speed's variance a filter of the model's input
  // explains (speed_follows_input.h); above kFollowsInput the offset is
  // not pinned either: a position error is then a change of the model's
  // dynamics. NaN: not told.
  double speed_input_share = NAN;
  bool speed_follows_input = false;
};

// The profile: SSE at every grid shift, the best (refined between grid
// points), every other term as refitted there; no interval yet.
ShiftProfile ProfileShift(const SeriesData& d, const EffectSet& current, const Effect& shift_effect,
                          const std::vector<std::size_t>& rows);

// The interval where the profile stays within SSE_min + chi2_1(0.95) q,
// q the residual's long-run variance along the profiled direction
// (ParameterCovariance::variance_along of the shift in the joint fit).
void ShiftInterval(ShiftProfile& profile, double q);

}  // namespace bead::explain
