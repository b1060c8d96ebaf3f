// Several beads in one profile: roads of one layer laid side by side, or
// beads welded next to each other, over the surface before them (the bed's
// reference line on layer 0, the layer below above it).
//
// Definitions (the gain d(x) = z_new(x) - z_below(x), as in added_bead.h):
//  - a region: a connected run of points with d above the edge floor
//    (dropouts up to max_gap_mm bridged) whose largest gain passes the
//    detection threshold; the bare point either side ends it. A region that
//    reaches the first or last point the profile saw is cut by the field of
//    view on that side: its outermost road there is flagged invalid
//    (RoadStatus::kCutByEdge), never measured as whole;
//  - the overlap model: each road's top is a circular arc (a liquid road's
//    free surface across its length where gravity is small beside surface
//    tension: a constant Laplace pressure, so a constant curvature), and
//    the roads are laid in order, each adding to the surface before it:
//    S_0 = 0, S_i(x) = max(S_{i-1}(x), C_i(x)); the measured gain is
//    S_n(x) + noise. The arcs (apex x, apex height, half-chord on the bed)
//    are fitted together by Levenberg-Marquardt; a road's material is what
//    it added over the surface before it, so the later road, which sits on
//    the earlier one's flank, keeps the material in the valley (a vertical
//    cut at the valley would give it to the earlier road);
//  - each road's area: the measured gain split by the model at each point:
//    a road owns the slab between S_{i-1} and S_i, the measured surface
//    taking the place of the top road's arc (the roads' areas add up to the
//    measured area); width: the road's footprint on the surface below (its
//    arc's chord there, the part hidden under a later road included; the
//    width the overlap models' spacing is over); centre: its arc's apex;
//    height: its arc's apex over the surface below;
//  - the number of roads: the crests of the smoothed gain that stand out
//    of the valleys beside them by threshold_sigmas noise sigmas (not the
//    threshold's floor in mm) and by min_valley_fraction of their height
//    (a flat top whose valleys have
//    filled, below the overlap models' critical spacing, shows one road
//    where there were more: the data cannot tell them apart);
//  - spacing: a road's centre less the centre of the road before it, over
//    that road's width (the overlap models' ratio): the flat-top overlap
//    model's critical ratio is 2/3 (Suryakumar et al. 2011: the critical
//    step 2w/3 for parabolic beads), the tangent overlapping model's 0.738
//    (Ding et al. 2015, Robotics and Computer-Integrated Manufacturing 31:
//    the critical centre distance 0.738 w): below them the valley
//    between roads is filled (the two papers as the issue names them).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "libbead/core/reservoir.h"

namespace bead::part {

struct RoadOptions {
  double min_threshold_mm = 0.05;  // the detection threshold: at least this ...
  double threshold_sigmas = 6.0;   // ... and this many noise sigmas
  // The detection threshold for a profile of noise `noise_mm`, mm.
  double Threshold(double noise_mm) const { return std::max(min_threshold_mm, threshold_sigmas * noise_mm); }
  double min_edge_floor_mm = 0.01;
  double edge_floor_sigmas = 2.0;
  double max_gap_mm = 1.0;
  // A point farther than this from the median of itself and its four
  // nearest neighbours is a spike, left out (profile/bead_heights.h's rule).
  double spike_mm = 0.5;
  // A crest counts as a road where the valley beside it lies this far
  // below it, as a fraction of its height (and by the detection threshold):
  // roads laid on each other's flanks leave valleys of a quarter to a half
  // of their height at 0.7 w (ellipses, parabolas); one bead's textured or
  // dimpled top, a few per cent.
  double min_valley_fraction = 0.1;
  bool laid_left_first = true;  // the laying order (false: right to left)
  int max_roads = 32;           // per region
};

enum class RoadStatus : uint8_t {
  kValid = 0,
  kCutByEdge,  // the field of view ends inside the road
  kNoFit,      // the overlap model did not converge on its region
};
const char* RoadStatusName(RoadStatus status);

struct Road {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  RoadStatus status = RoadStatus::kNoFit;
  double center_x_mm = kNaN, area_mm2 = kNaN, width_mm = kNaN, height_mm = kNaN;
  double spacing_over_width = kNaN;  // to the road before it in its region; NaN for the first
  double fit_rms_mm = kNaN;          // the region's residual RMS
  // Its area had the roads been laid in the other order: the profile
  // cannot tell the two apart (the model's top, the highest cap, is the
  // same either way), only the split moves.
  double area_other_order_mm2 = kNaN;
  bool valid() const { return status == RoadStatus::kValid; }
};

// x: the profile's valid points, increasing; gain: z over the surface below
// at each (NaN where the surface below is unknown); noise_mm: the
// profile's noise. The roads left to right.
std::vector<Road> FindRoads(std::span<const float> x, std::span<const double> gain, double noise_mm,
                            const RoadOptions& options = {});

// The roads of a scan, tallied: how many profiles held how many roads, the
// roads cut by the field of view or not fitted, and the spacings.
struct RoadsSummary {
  std::map<std::size_t, std::size_t> profiles_by_count;  // roads found -> profiles
  std::size_t roads = 0, cut_by_edge = 0, no_fit = 0;
  // Between valid neighbours (a bounded sample of them: core/reservoir.h).
  Reservoir spacing_over_width;
  // Each valid road's |area in the other order / area - 1|, where it has a
  // valid neighbour: how much the split rests on the order the user gave.
  Reservoir order_change;
  // A profile's roads, left to right, laid in that order or (false) the
  // other: each pair's spacing is held by the road laid after the other.
  void Add(const std::vector<Road>& roads, bool laid_left_first);
  double MedianSpacing() const;  // NaN without a pair of valid neighbours
  // The median spacing against the overlap models' critical ratios, in
  // words (empty without a spacing).
  std::string SpacingInWords() const;
  // What the other laying order would make of the areas, in words (empty
  // where no road has a neighbour); left_first: the order used.
  std::string OrderInWords(bool left_first) const;
};

// The flat-top overlap model's critical centre distance over the width,
// 2/3 (Suryakumar et al. 2011), and the tangent overlapping model's, 0.738
// (Ding et al. 2015, RCIM 31).
inline constexpr double kFlatTopCriticalRatio = 2.0 / 3.0;
inline constexpr double kTangentCriticalRatio = 0.738;

}  // namespace bead::part
