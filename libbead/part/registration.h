// The lateral registration of a part's new profile on the surface below
// (the definition: part/added_bead.h). Two ways to the same least:
//  - tracked: Gauss-Newton on the truncated cost from the shift of the
//    profile before in the same pass (the passes' shift changes slowly
//    along the path), the points whose gain is under the cap weighed by
//    their variance; its sigma from the cost's curvature there,
//    1 / sqrt(sum g^2 / variance) with g the slope of the surface below,
//    at least a wall's sampling, spacing / sqrt 12;
//  - scanned: the cost on a grid of shifts over the warm window (or the
//    whole range where the window's band within 4 of its least reaches its
//    end, or, the shift unconstrained, its bracket does: hidden_sigma; the
//    range widened where its least lies at its end; a pass's first
//    searches also look over the widest, a quarter of the surface below's
//    span), its sigma from the range within 4 of the least.
// A profile is tracked where a start is given and the track converges
// inside the warm window with the shift constrained (the layer below
// showing beside the new bead: part/added_bead.h); scanned otherwise (the
// first profile of a pass, a track that wandered off, found no slope to
// move on, or settled where too little of the layer below shows, as it
// does in a wrong local least).
#pragma once

#include <limits>
#include <span>

#include "libbead/part/added_bead.h"
#include "libbead/part/grid_costs.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

struct Registration {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double shift = 0.0, sigma = kNaN, rms = kNaN;
  int points = 0;
  bool constrained = false;
  bool at_end = false;   // the scan's band within 4 of the least reached the search's end
  bool tracked = false;  // found by the track, not the scan
  // The shifts whose cost is within one point's disagreement (the cap) of
  // the least, as a uniform sigma (range / sqrt 12): where the layer below
  // may lie and stay hidden (a bead covering the one below, its ends over
  // the old ends: the bare bed beside it brackets the shift, nothing inside
  // the bracket tells one shift from another). The sigma is at least this.
  // A scan's own; a track carries the pass's last.
  double hidden_sigma = 0.0;
  // The shifts within the cap of a scan's least reach its end: the bracket
  // may reach further, hidden_sigma is then a floor. An unconstrained warm
  // window's scan so bracketed is searched over the whole range.
  bool bracket_open = false;
};

// The noise and the point spacing the registration weighs gains by.
struct RegistrationScale {
  double tau = 0.0;      // the detection threshold (the cap: tau^2 in noise variances)
  double noise = 0.0;    // one point's noise, mm
  double spacing = 0.0;  // the points' median spacing, mm
  // One point's disagreement at most: tau^2 in noise variances.
  double Cap() const { return tau * tau / (noise * noise); }
};

// x, z: the new profile's points (bed frame, x increasing); start: the
// shift found for the profile before in the same pass (nullptr: none);
// grid: the points on the surface below's grid (part/grid_costs.h), where
// the caller made it (nullptr: made here where they lie on it);
// start_hidden_sigma: the pass's last hidden_sigma, which a track carries;
// search_wide: with no start, first look over the widest range (a quarter
// of the surface below's span) for a least beyond +-max_shift_mm: the
// pass's first searches (a coarse scan over that range; the whole search
// 0.09 to 0.18 ms on the twin's 801 points, where a profile tracked from
// the last shift takes about 1.3 us: the caller asks twice a pass, not
// every profile).
Registration Register(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                      const RegistrationScale& scale, const AddedBeadOptions& options, const double* start,
                      const PointsOnGrid* grid = nullptr, double start_hidden_sigma = 0.0, bool search_wide = false);

// A shift found elsewhere (r.shift, r.sigma, r.hidden_sigma: a tracker's
// own steps, part/part_profile_processor.h) settled as Register settles its
// own: the points where the surfaces agree there (r.points, r.rms), its
// sigma at least the hidden one, and whether it is constrained (sigma
// within options.max_shift_sigma_mm and the layer below sloped beside the
// new bead in at least options.min_feature_points points).
void SettleShift(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                 const RegistrationScale& scale, const AddedBeadOptions& options, const PointsOnGrid* grid,
                 Registration& r);

// The truncated cost at shift s (in noise variances, each point's at most
// the scale's cap) with its gradient and Gauss-Newton curvature in s over
// the points under the cap (d(gain)/ds is the slope of the surface below
// there); on the grid's sums where the points lie on it (grid not null).
PointsOnGrid::Local LocalCost(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below, double s,
                              const RegistrationScale& scale, const PointsOnGrid* grid);

// The points where the new profile (x, z) agrees with the surface below
// at them (`under`, NaN where unknown) on a flank of it, by Settle's rule
// above (the rise to the next point over 4.5 noises' worth, or a run of
// two over three), the second rule counted only where the first gives
// fewer than `enough`: the count where it is under `enough`, else at least
// `enough` (counting stops once the first rule has found that many).
int FlankPoints(std::span<const float> x, std::span<const float> z, std::span<const float> under,
                const RegistrationScale& scale, int enough);

}  // namespace bead::part
