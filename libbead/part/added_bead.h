// What one layer added to a part at one profile: the new surface over the
// surface before it (the bed's reference line for layer 0, the layer
// below for the others; part/surface_below.h), both in the bed frame.
//
// Definitions (the wheel's, profile/bead_geometry.h, with the surface
// below in place of the reference line):
//  - gain d(x) = z_new(x) - z_below(x - s), s the lateral shift between
//    the two passes (registration, below);
//  - the bead: the connected run of points (dropouts up to max_gap_mm
//    bridged) with d above the detection threshold max(min_threshold_mm,
//    threshold_sigmas * noise) whose integral is largest, extended outward
//    while d stays above the edge floor and does not rise outward by more
//    than kFootRiseNoises noises (a bead's side falls toward its foot; a
//    gain rising again beyond it is something else: the layer below's
//    wall beside the end, interpolated across its cell by a registration a
//    fraction of a spacing off, a wall's height off at one point); the
//    first point beyond each foot is where the new surface meets the old;
//  - area: the trapezoid integral of max(d, 0) from the bare point left of
//    the bead to the bare point right of it, a bare point's d at most the
//    edge floor (it is not the bead's); width: between the edges,
//    where d crosses the edge floor (linear between the foot and the bare
//    point); height: d at the crest (the median of three around the
//    highest new point); centre: the middle of the bead's top, halfway
//    between where the new surface falls below the crest by half the
//    lesser of its drops to the two feet (a flat top's middle as a round
//    one's; the gain's centroid leans toward an overhanging side); where
//    that drop is under six noises, the vertex of the parabola through the
//    new surface within a fifth of the width of its highest point;
//  - registration: s minimises the mean squared gain of the points outside
//    the bead (where the old surface is still what the sensor sees: the
//    bed, a lower layer's flank that the new bead does not cover): s
//    minimises the truncated squared gain over all points (each in its
//    noise variance, capped at the threshold's: a point inside the new bead
//    costs the same at every shift), on a grid of a quarter point spacing
//    over +-max_shift_mm (doubled while the least lies within warm_half_mm
//    of the range's end, up to a quarter of the surface below's span; the
//    pass's first profiles also look over that whole span for a least
//    beyond the range), averaged over one spacing. s is the middle of the
//    shifts within 1 of the least cost, its sigma a quarter of the range
//    within 4, at least spacing / sqrt 12, and at least the uniform sigma
//    of the range within the cap (one point's disagreement: where the
//    layer below may lie hidden; part/registration.h). Given the pass's recent shift,
//    the same least is first followed from it by Gauss-Newton, its sigma
//    from the cost's curvature (part/registration.h); the grid is searched
//    where that does not settle constrained. Where the layer below shows
//    nowhere beside the new bead (fewer than min_feature_points sloped
//    points agree), or the range reaches the search's end, or its sigma
//    exceeds max_shift_sigma_mm (or one point spacing, if larger: the
//    sigma's floor is spacing / sqrt 12), s is not constrained: the layer below may
//    lie anywhere it stays hidden. The area is still measured at the least
//    cost (a hidden bead's place hardly moves it), but the bead's offset
//    from the one below is not reported: the pass's shift and the wall's
//    wander cannot be told apart there;
//  - noise: from second differences of the new profile (a smooth surface
//    adds little to them): 1.4826 median|z_i - 2 z_i+1 + z_i+2| / sqrt 6,
//    at least 0.002 mm.
#pragma once

#include <cstdint>
#include <algorithm>
#include <limits>
#include <span>

#include "libbead/part/surface_below.h"

namespace bead::part {

struct AddedBeadOptions {
  double min_threshold_mm = 0.05;
  double threshold_sigmas = 6.0;
  // The detection threshold for a profile of noise `noise_mm`, mm.
  double Threshold(double noise_mm) const { return std::max(min_threshold_mm, threshold_sigmas * noise_mm); }
  double min_edge_floor_mm = 0.01;
  double edge_floor_sigmas = 2.0;
  double max_gap_mm = 1.0;
  // The lateral registration's search range, mm either way (at most a
  // quarter of the surface below's span; widened where the least lies at
  // its end: part/registration.cc) ...
  double max_shift_mm = 3.0;
  // ... and the largest sigma at which its shift is used, mm (at least
  // one point spacing: a coarser sensor places a lone wall no closer).
  double max_shift_sigma_mm = 0.05;
  // Given the shift of the profile before in the same pass, the search
  // looks this far either side of it first (the whole range when the best
  // lies at that window's end), mm (at least six point spacings, at most
  // half the range).
  double warm_half_mm = 0.3;
  int min_bead_points = 3;
  // Fewest points outside the bead where the surface below slopes (a rise
  // over a point spacing no flat bed's noise makes by chance,
  // part/registration.cc: a lower layer's flank) for the shift to count as
  // found. (Three, once the bed's noise no longer counted, left out a
  // twin wall's rows whose lower bead showed at two: 262 shifts found of
  // 307, their offsets as good.)
  int min_feature_points = 2;
};

enum class AddedStatus : uint8_t {
  kValid = 0,
  kTooFewPoints,     // the profile holds fewer than 10 valid points over the surface below
  kNoSurfaceBelow,   // the layer below (the bed, on layer 0) is not known here
  kNoBead,           // nothing stands above the threshold over the surface below
  kBeadEdgeNotSeen,  // the bead runs to the end of what both scans saw
  // On layer 0, the rig's reference areas hold no bare flat bed to measure
  // against: a bead stands in them, or they are no line to the profile's
  // noise (a bead filling them, or a curved bed).
  kBeadInReferenceArea,
  kReferenceNotALine,
  // The new surface lies under the surface before it by the threshold over
  // more points than stand over it by the threshold, and over kUnderShare
  // of its points. A layer only adds material: above layer 0 the two scans
  // are not where their frames say (most often /profiles/frame_z_mm not the
  // head's height: absent, so 0, or in other units or sign); on layer 0 z
  // is a distance, not a height (the bead a trough), or the bed line stands
  // over the bed (reference areas on something raised).
  // Not measured (AddedBead::under_mm says by how much).
  kUnderSurfaceBelow,
  // Above layer 0: the bare bed in both of the rig's reference areas (bare
  // in every layer) lies off where the layer below's scan has it, by the
  // threshold, the same way and by the same to within it (AddedBead::
  // bed_off_mm, signed): the two scans are not where their frames say
  // (frame_z_mm, z read as a distance). Not measured.
  kBedMoved,
};
inline constexpr double kUnderShare = 0.1;
const char* AddedStatusName(AddedStatus status);

struct AddedBead {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  AddedStatus status = AddedStatus::kTooFewPoints;
  double area_mm2 = kNaN;     // what the layer added to the surface before it
  double width_mm = kNaN;     // where the new surface stands above the old
  double height_mm = kNaN;    // the gain at the crest
  double center_x_mm = kNaN;  // the bead's top, this pass's bed frame
  double shift_mm = 0.0;      // the layer below moved by this into this pass's frame (least cost)
  double shift_sigma_mm = kNaN;
  double shift_hidden_sigma_mm = 0.0;  // part/registration.h's hidden_sigma
  bool shift_constrained = false;
  double registration_rms_mm = kNaN;  // the gain's RMS outside the bead (0 expected)
  // The gain at each foot (the outermost bead point, left and right): the
  // height of the wall the area's trapezoid places within a point spacing.
  double edge_left_mm = kNaN, edge_right_mm = kNaN;
  double noise_mm = kNaN;
  int outside_points = 0;  // points where the two surfaces agree (|gain| under the threshold)
  // Where kUnderSurfaceBelow: the median gain of the points under the
  // surface before it (negative), mm.
  double under_mm = kNaN;
  // Where kBedMoved: the mean of the two reference areas' median gains, mm.
  double bed_off_mm = kNaN;
  bool valid() const { return status == AddedStatus::kValid; }
  // The two scans are not where their frames say (kUnderSurfaceBelow,
  // kBedMoved): nothing over the surface below is to be trusted.
  bool FramesDisagree() const { return status == AddedStatus::kUnderSurfaceBelow || status == AddedStatus::kBedMoved; }
  // The area's own noise variance, mm^4: its trapezoids over the bead's
  // width / spacing points, each a spacing times a gain of the point's noise
  // and the surface below's (as much again: a layer below's point, or the
  // bed line's offset over the bead), width spacing 2 noise^2.
  double AreaNoiseVar(double spacing_mm) const { return 2.0 * width_mm * spacing_mm * noise_mm * noise_mm; }
};

// A profile's noise from its second differences (the definition above).
double ProfileNoiseMm(std::span<const float> z);
// The median spacing of increasing x (one stray point far off does not
// move it), at least 1e-4 mm; 0.05 mm where there are fewer than two.
// Where more than half the steps agree within a thousandth of a step (a
// sensor's uniform points), the median lies among them and their mean is
// given: the same to that thousandth, without sorting.
double PointSpacingMm(std::span<const float> x);

// x, z: the new profile's valid points in the bed frame, x increasing.
// register_shift = false: s = 0 (the bed's line, fitted on this profile).
// start_shift: where the pass's shift was last found (nullptr: nowhere
// yet), start_hidden_sigma: its hidden sigma (part/registration.h);
// spacing_mm: PointSpacingMm(x), noise_mm: ProfileNoiseMm(z), where the
// caller has them (NaN: found here); search_wide: part/registration.h.
AddedBead MeasureAddedBead(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                           bool register_shift, const AddedBeadOptions& options = {},
                           const double* start_shift = nullptr, double spacing_mm = AddedBead::kNaN,
                           double start_hidden_sigma = 0.0, double noise_mm = AddedBead::kNaN,
                           bool search_wide = false);

}  // namespace bead::part
