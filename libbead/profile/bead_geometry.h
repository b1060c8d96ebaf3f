// Bead geometry of one profile, measured against its reference line.
//
// Definitions (all along and perpendicular to the reference line, so a
// sensor roll does not change them):
//  - height h of a point: its perpendicular distance above the line;
//  - the bead is looked for between the reference areas (from 16 points
//    inside one to 16 inside the other; nothing beyond them is looked at):
//    the connected run of points with h above the detection threshold,
//    max(min_threshold_mm, threshold_sigmas * reference RMS), whose
//    integral is largest; spikes (one or two points wide) are first put on
//    the chord between their neighbours, and dropouts up to max_gap_mm
//    long inside it are bridged;
//  - feet: from the bead outward, the points still above the noise floor
//    max(min_edge_floor_mm, edge_floor_sigmas * reference RMS) belong to
//    it (a gently sloped side dips below the detection threshold before it
//    meets the surface); the first point beyond is bare surface;
//  - edges (the sub-sample model): below the first bead sample the
//    outline continues the parabola through the first three bead samples
//    (spikes left out) to the surface when it meets it before the bare
//    sample (a sloped wall; the edge is that root); otherwise a wall stands
//    somewhere in the gap (seen from above, as undercut makes it): the
//    trapezoid to the bare sample, right on average wherever the wall
//    stands, the edge at the gap's middle; width = distance between edges;
//  - area: the trapezoid integral of h from the first to the last bead
//    sample, each end of a sloped wall corrected by the Euler-Maclaurin
//    term spacing^2 / 12 * slope, plus the two edge pieces: exact for a
//    parabola or straight walls, unbiased over sampling phase otherwise;
//  - height: the largest median of three neighbouring heights in the bead
//    (a robust maximum: one stray point cannot set it);
//  - centre: x of the area centroid, projected onto the reference line.
// A profile that cannot be measured gets a status other than kValid and
// NaN values; it is never dropped.
#pragma once

#include <cstdint>
#include <limits>

#include "libbead/core/rig.h"
#include "libbead/profile/point_set.h"
#include "libbead/core/profile_view.h"
#include "libbead/profile/reference_line.h"
#include "libbead/profile/workspace.h"

namespace bead {

struct BeadOptions {
  // Detection threshold: the larger of this height, mm ...
  double min_threshold_mm = 0.05;
  // ... and this many reference-line residual RMS.
  double threshold_sigmas = 6.0;
  // A point whose height differs by more than this from the median of
  // itself and its four nearest neighbours is a spike (reflection) and is
  // dropped; up to two adjacent spikes are caught.
  double spike_mm = 0.5;
  // Gaps between valid points up to this long are bridged inside a bead;
  // a longer gap ends it.
  double max_gap_mm = 1.0;
  // The feet end where the height falls to the larger of this, mm ...
  double min_edge_floor_mm = 0.001;
  // ... and this many reference-line residual RMS.
  double edge_floor_sigmas = 2.0;
  // A foot is carried outward only while the height does not rise over the
  // point before by more than this, mm (infinite: the wheel, whose feet
  // run over a bare line; a part's over the layer below, whose wall beside
  // the bead's foot makes the gain rise again: part/part_profile_processor.h).
  double max_foot_rise_mm = std::numeric_limits<double>::infinity();
  // Fewest points above threshold that make a bead.
  int min_bead_points = 3;
  // Fewest valid points a profile needs at all.
  int min_profile_points = 10;
};

enum class ProfileStatus : uint8_t {
  kValid = 0,
  kTooFewPoints,         // fewer valid points than min_profile_points
  kNoReference,          // a reference area holds too few valid points
  kNoBead,               // nothing stands above the threshold
  kBeadEdgeNotSeen,      // the bead's foot runs into a long dropout, or far into a reference area
  kBeadInReferenceArea,  // the bead reaches into a reference area
};

// Short snake_case name of a status, for CSV and logs.
const char* StatusName(ProfileStatus status);

struct BeadGeometry {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  ProfileStatus status = ProfileStatus::kTooFewPoints;
  double area_mm2 = kNaN;
  double width_mm = kNaN;
  double height_mm = kNaN;
  double center_x_mm = kNaN;
  double left_edge_x_mm = kNaN;
  double right_edge_x_mm = kNaN;
  // Standard uncertainty of area_mm2 from sampling and noise: each edge
  // lies anywhere within its bracketing segment (h_edge * ds / sqrt(12)),
  // each height carries the reference RMS (sum of ds^2), and so does the
  // line's offset over the width (rms * width / sqrt(points used)).
  double area_sigma_mm2 = kNaN;
  double threshold_mm = kNaN;  // detection threshold used
  int bead_points = 0;         // valid points above threshold in the bead
  int dropped_points = 0;      // NaN or spike points between the bead's edges
  ReferenceLine reference;

  bool valid() const { return status == ProfileStatus::kValid; }
};

// Measures the bead of the prepared points (point_set.h, the last set the
// workspace prepared) against `line`; nothing is allocated.
BeadGeometry MeasureBead(const PointSet& points, const ReferenceLine& line, const ReferenceArea& left,
                         const ReferenceArea& right, const BeadOptions& options, ProfileWorkspace& workspace);

}  // namespace bead
