// What a sensor looking down cannot see on a part: a bead that sinks into
// the surface below and overhangs it hides the groove under its sides, as
// a rounded bead hides its undercut on the wheel (the thesis, 4.4: the
// occlusion bias inflates the measured area). The area a layer visibly
// added (part/added_bead.h) counts that groove as material.
//
// Model: the new bead's cross-section is a superellipse (centre x0, z0;
// semi-axes A across, B up; exponent p, part/superellipse.h: p = 2 the
// ellipse of the thesis' rounded beads and the twin's, a box above, a
// diamond below; or p < 0, a stadium: a flat top with quarter-ellipse
// ends, a tamped bead's, whose flat bottom is pressed onto what lies under
// it), its material what lies inside it above the surface before it. The
// sensor sees max(surface below, the bead's top). Where the bead
// overhangs, its ends show as walls in the seen profile and the bead
// is placed there, its height solved over its top, and its shape (aspect
// and exponent) with it until the layer's is pooled (part/silhouette.h);
// where they do not, an ellipse (the layer's pooled superellipse, where it
// is not an ellipse) is fitted to the profile's points around
// the bead by Levenberg-Marquardt (the surface below known, moved by the
// registration's shift; its sigma the fit's covariance, residual variance
// times (J^T J)^-1, carried through the groove's gradient). The groove is
// the part of the bead's outline's shadow that lies above the surface
// below: the integral of max(0, z0 - B s(u) - z_below(x)) over the bead's
// width. Where the bead's sides are not seen steep enough to place its
// widest point, the sigma says so.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "libbead/part/groove_window.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

// Why a bead's outline is not one the model knows (its groove then not
// estimated: HiddenGroove::ok false): the shape placed on its top
//  - floats: it stands clear of the surface it was laid on everywhere
//    under it, by more than a tenth of the bead's height (a bead touches
//    what it was laid on; a flat-topped bead with rounded sides, a tamped
//    bead, got an ellipse that floats, before the stadium was a shape);
//  - top_off: the layer's shape (its pool: part/layer_grooves.h) misses
//    its beads' seen tops by over kTopOffNoise times their tolerance
//    (TopTolerance: their noise, kTopShapeHeights of their height that
//    a bead's top may leave any shape of the family, and what the ends'
//    cells leave at the points' spacing, TopSamplingMm; the median over the
//    pooled rows of each top's RMS; the right shape leaves the noise:
//    1.0-1.1 times it on the twin's walls and contours, while
//    single rows reach 8-18 times it at mixed points and lost points'
//    edges, one in a thousand: a row alone is not judged by it);
//  - family_edge: its exponent is the family's last (or first): the bead
//    is boxier (or more pointed) than any of the model's shapes;
//  - ends_off: in most of the layer's rows placed at their walls, the
//    shape solved over the top puts an end outside the cell its wall shows
//    (Silhouette::shape_consistent): no shape of the family has both that
//    top and those walls. On the right shape no row of a layer's pool does
//    so (twin walls, contours and pipes; a second generator's pressed
//    ellipses at aspects 0.35-0.7, 20-30 um noise, 1.2-2 mm layers); on a
//    lens (two parabolas meeting at a corner at each end), 90-100 % do,
//    while its pooled top misses by only 1.7 times the noise and its
//    corrected areas came out 11 % high, at 17-85 of their sigmas.
enum class OutlineMisfit : uint8_t { kNone = 0, kFloats, kTopOff, kFamilyEdge, kEndsOff };
inline constexpr double kTopOffNoise = 3.0;
// What the model's shapes leave on a bead's top whatever the noise: 4-7 um
// on the twin's 2.4 mm beads and a second generator's pressed ellipses,
// 0.2-0.3 % of the height (not traced further; the pooled aspect held over
// a layer whose sizes vary, the exponent's grid and the points' footprint
// are what the shapes cannot follow). Judged
// against the noise alone, a sensor of 1 um (its noise read at the 2 um
// floor) saw the twin's own ellipses miss by 2.6-3.6 times it, and four of
// six layers went uncorrected, 15-30 % high. A top's miss of a small share
// of the height moves the groove under it by that share of the groove,
// a few thousandths of the area: 0.5 % is allowed beside the noise. A
// tamped bead's flat top missed any superellipse's by 120-210 um (8-14 %
// of its height; now a stadium's), a lens's misses by 65-77 um at a 10 um
// noise: still told apart.
inline constexpr double kTopShapeHeights = 0.005;
inline double TopTolerance(double noise_mm, double height_mm) {
  return std::hypot(noise_mm, kTopShapeHeights * height_mm);
}
// What the points' spacing leaves on the top of the right shape, placed by
// ends that each lie anywhere in a cell a spacing s wide (sigma s / sqrt 12;
// the centre's and the half-width's s / sqrt 24 each): over the top's
// points (|u| < 0.9, uniform in u) an ellipse's top moves by b / a times
// u / sqrt(1 - u^2) per mm of centre and u^2 / sqrt(1 - u^2) per mm of
// half-width, whose mean squares there are 0.636 and 0.366:
// sqrt(1.002) (b / a) s / sqrt 24 = 0.204 (b / a) s (the ellipse's slopes
// as the scale for every shape; their refit height and size take up part
// of it: an upper bound). (Left out, pressed ellipses seen at points 0.2 mm
// apart, 10 um of noise, had a whole layer's tops miss by 4.0 times the
// noise and height's tolerance and the layer go uncorrected, "not their
// shape", the flow fit -87 %; the sampling's 0.020 mm is 1.4 times that
// tolerance. At 0.05 mm it is 0.005 mm.)
inline double TopSamplingMm(double aspect, double spacing_mm) {
  return std::isfinite(aspect) ? 0.204 * aspect * spacing_mm : 0.0;
}
// The tolerance the layer's shape is judged by (OutlineMisfit::kTopOff): the
// above and the spacing's, in quadrature.
inline double TopTolerance(double noise_mm, double height_mm, double sampling_mm) {
  return std::hypot(TopTolerance(noise_mm, height_mm), sampling_mm);
}
// A top's RMS miss over that tolerance, its shape's aspect and the points'
// spacing setting the sampling's share.
inline double TopMissTolerances(double top_rms_mm, double noise_mm, double height_mm, double aspect,
                                double spacing_mm) {
  return top_rms_mm / TopTolerance(noise_mm, height_mm, TopSamplingMm(aspect, spacing_mm));
}
inline constexpr double kFloatsHeights = 0.1;

struct HiddenGroove {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool ok = false;
  OutlineMisfit misfit = OutlineMisfit::kNone;
  double hidden_mm2 = kNaN;  // the groove under the overhangs
  // Where an end was placed in a gap beside its wall (part/silhouette.h):
  // what the area seen's trapezoid across the gap counted wrongly (add it).
  double seen_adjust_mm2 = 0.0;
  double sigma_mm2 = kNaN;   // its 1-sigma
  double fit_rms_mm = kNaN;  // the fit's (NaN: placed at the silhouette, not fitted)
  double top_rms_mm = kNaN;  // the seen top's points about the shape's top (within 0.9 of its half-width)
  double aspect = kNaN;      // the bead's b / a
  double exponent = kNaN;    // its superellipse's (part/superellipse.h; a fit's: 2)
  // Placed at the silhouette with the shape free: the aspect's and
  // exponent's variances from where the ends lie in their cells
  // (part/silhouette.h), and the left end's place (bed frame).
  double aspect_end_var = 0.0, exponent_end_var = 0.0, left_end_mm = kNaN;
  // The same with each end whose wall holds mixed points anywhere over the
  // width they widened its cell by (Silhouette::aspect_mixed_var).
  double aspect_mixed_var = 0.0, exponent_mixed_var = 0.0;
  // What the exponent grid's steps leave in them, and whether the top
  // agrees with the walls' cells (part/silhouette.h: else not pooled).
  double aspect_grid_var = 0.0, exponent_grid_var = 0.0;
  bool shape_consistent = true;
  // With the shape free, placed or its walls unsolved: the solve's
  // Silhouette::family_log_ratio (NaN where none was solved).
  double family_log_ratio = 0.0;
  // Placed at the silhouette: whether either end's wall held a mixed point.
  bool end_mixed = false;
  // Where the top placed the free shape's ends in their cells
  // (Silhouette::end_place): where the next row's placement starts.
  double end_place[2] = {kNaN, kNaN};
  // Placed at the silhouette: the sigma holds the area seen's edges too
  // (they move with the ellipse's ends; part/silhouette.h).
  bool at_silhouette = false;
  // The ellipse placed or fitted, its centre from the bead's centre and the
  // surface below there: where the next profile's fit starts.
  double dx0 = kNaN, dz0 = kNaN, a = kNaN, b = kNaN;
  // Placed at the silhouette with the shape free: the half-width its
  // aspect and exponent belong to (Silhouette::shape_a); and, a stadium on
  // a flat surface, its half-height from its top's height over that
  // surface (hidden_groove.cc: PressedHalfHeight; NaN: not so).
  double shape_a = kNaN, pressed_half_mm = kNaN;
  // Fitted, with no shape held, where both its ends showed walls but the
  // free shape its top solved did not stand over them (part/silhouette.h:
  // AtSilhouette's walls_unsolved): its top and walls, to the noise and the
  // ends' cells, do not pin its shape.
  bool walls_unsolved = false;
  // Placed at its wall inside a rise over the cliff of the layers below
  // (part/silhouette.h: AtTheWalls), the doubt between the two in the sigma.
  bool inside_cliff = false;
};

// x, z: the profile's valid points in the bed frame (x increasing); below:
// the surface before it, moved by `shift` (z_below(x) = below.At(x - shift))
// known to shift_sigma (0 where not registered), its variance in units of
// noise_mm^2 (surface_below.h); center, width, height:
// the bead as part/added_bead.h measured it; pooled: the layer's shape to
// hold (nullptr: solved here); free_exponent: with none held, a fit's
// (an earlier layer's that is not an ellipse's, carried; else 2);
// stadium_only: with none held, the stadium's family alone placed at the
// walls (part/silhouette.h: FreeSolve).
HiddenGroove EstimateHiddenGroove(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                                  double shift, double shift_sigma, double noise_mm, double center, double width,
                                  double height, const PooledShape* pooled = nullptr,
                                  const HiddenGroove* previous = nullptr, double free_exponent = 2.0,
                                  bool stadium_only = false);

}  // namespace bead::part
