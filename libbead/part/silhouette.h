// A wall's bead placed at its silhouette, with no search (part/hidden_groove.h).
//
// A bead that overhangs the surface below shows a sensor looking down its
// top, down to its widest point, and then, beyond it, the surface below: the
// seen profile rises at each end of the ellipse by a wall as high as its
// widest point stands over the surface below. The ends are where the gain
// rises most from one point to the next in the outer third of the bead's
// run on each side; each lies somewhere between those two points (its
// cell), and is placed halfway, or, with the layer's shape held, where the
// held shape's top puts it within the cell, weighed against the cell's
// middle by their variances (silhouette.cc: PlaceByTop; the area seen
// across each wall's cell then taken as the bead placed shows it, not as
// the trapezoid). With the ends placed, the top's height z0 +
// b s(u) (part/superellipse.h: s = sqrt(1 - u^2) for the ellipse) is linear
// in z0 and b (z0 alone with the aspect b / a held): solved by least squares
// over the top's points within 0.9 of the half-width (the outer tenth, where
// the top is steeper than twice b / a, turns with the ends' places inside
// their cells). The exponent, where it is not held, is the one of
// SuperellipseGrid whose solution leaves the least residual, refined
// between its neighbours by the parabola through the three (in ln p).
// For the layer's pool, the free shape is solved again with each end placed
// within its cell where the top reaches the outermost point's height
// (part/silhouette_top.h); the bead itself stays placed halfway there (its
// shape is what is being solved; a held shape is what places the ends).
// Placed halfway with the shape held too, a wall whose ends sweep through
// their cells as it wanders gave every row's groove the phase's error: on
// a generator's wall at 0.1 mm spacing a sawtooth of +-0.4 mm^2 over 20 mm
// of path on the sixth layer, the flow fit 84.5 % (89.8 % placed by the
// top).
//
// A least-squares fit of all four parameters to every point would place
// the ends to within a fraction of a cell, but its residual jumps wherever
// an end passes a point (the seen profile's wall): Levenberg-Marquardt
// stalls against such jumps, and the least it reaches depends on where it
// starts. On the twin's walls and contours the fit from eight starts
// corrected a profile's area to 0.2-0.3 % (median); placed at the
// silhouette, to 0.05-0.1 %.
//
// Where an end's place in its cell is unknown, the area seen and the groove
// move together (the seen area loses the wall's height times the step, the
// groove about as much; the ellipse itself is thin there): the variance
// counts their difference, not each. Not where the profiler averages over
// a footprint (PooledShape::footprint) and the end's wall holds a mixed
// point: the area seen, integrating the spots, is the same wherever the
// end lies, and the groove's change is counted whole.
#pragma once

#include <cmath>
#include <optional>

#include "libbead/part/groove_window.h"

namespace bead::part {

struct Silhouette {
  Ellipse e;  // its exponent the grid's where free
  // Where the shape is free: the exponent refined between the grid's, and
  // the aspect there, with the ends placed within their cells by the top
  // (part/silhouette_top.h: the pool's values); where held, the held ones.
  double exponent = 2.0, aspect = 0.0;
  // Where the free shape's ends are placed by the top: each end's sigma
  // (NaN: anywhere in its cell).
  double end_sigma[2] = {NAN, NAN};
  // ... and where each settled: its share of the way across its cell (a
  // row's placement starts from the row before's).
  double end_place[2] = {NAN, NAN};
  // ... and the half-width between them: the aspect and exponent are the
  // shape's at that half-width, not at the cells' middles' (e.a).
  double shape_a = NAN;
  // false where the top places an end outside the cell its wall was found
  // in by more than three of its sigmas: the wall taken for the end is not
  // the bead's (the layer below's wall, interpolated across a registration
  // a fraction of a spacing off, rising beside it). Its shape is not pooled.
  bool shape_consistent = true;
  // Where an end's wall holds a point that is neither the top nor the
  // surface below (part/silhouette_top.h: OnTheTop).
  bool end_mixed[2] = {false, false};
  // Whether each wall's rise (left, right) steps over a cliff: the surface
  // below changes across it by more than the gain rises (a cliff sampled at
  // another pass's points leaves gains of about its step: the rise may be
  // that, not the bead's end; SilhouetteScale::wall_rank takes another).
  bool over_cliff[2] = {false, false};
  double cell[4] = {};                     // the left end lies in [cell[0], cell[1]], the right in [cell[2], cell[3]]
  double wall_left = 0, wall_right = 0;    // the seen wall at each end: z0 over the surface below there, mm
  double residual_variance = 0.0;          // the top's points', mm^2
  double z0_var = 0, b_var = 0, z0_b = 0;  // the solution's covariance over the residual variance (b's 0 where held)
  double mean_s = 0.0;                     // the mean of sqrt(1 - u^2) over those points
  // z0's and b's derivatives in the place of each end (left, right), the
  // top re-solved with the same points.
  double z0_by_end[2] = {}, b_by_end[2] = {};
  // z0's derivative in the exponent where the shape is held (b then held
  // too): the top re-solved with the same points.
  double z0_by_exponent = 0.0;
  // Where the shape is free: the aspect's and exponent's variances from
  // where the ends lie (each solved again with an end moved by half its
  // cell, times the end's sigma). Rows whose ends share their places in the
  // cells (a bead whose width changes by less than a cell) share what the
  // places leave: a layer's pool does not average it away.
  double aspect_end_var = 0.0, exponent_end_var = 0.0;
  // The same with each end whose wall holds mixed points (end_mixed)
  // anywhere over the width they widened its cell by (uniform), whatever
  // the top says: the top places it as if each point were the surface at
  // its x, which a point averaged over a spot of unknown shape is not; what
  // that leaves is the same in every row (one profiler, one bead shape): a
  // pool does not average it.
  double aspect_mixed_var = 0.0, exponent_mixed_var = 0.0;
  // What the exponent grid's steps leave in them (the same in every row of
  // a shape: a pool does not average it).
  double aspect_grid_var = 0.0, exponent_grid_var = 0.0;
  // Where the shape is free: ln of the superellipse's least residual
  // variance over the stadium's, both solved on the same points (0 where
  // the superellipse follows the top within its share and the stadium is
  // not tried; NaN where either family solves none): a row's evidence
  // between the two families, which a layer's pool sums (part/
  // layer_grooves.cc: OfOneFamily).
  double family_log_ratio = 0.0;
  // With the shape held, each end is placed by the top (in a gap, lost
  // points beside its wall, where the top fits best); the area seen across
  // each wall's cell as the bead placed shows it, less the trapezoid the
  // area seen counted across it (mm^2; add it to the area seen).
  double seen_adjust = 0.0;
};

// What a silhouette is: the bead's run stands more than `floor` over the
// surface below; each end's wall rises by more than `rise` (mm). wall_rank:
// which of the rises over `rise` in the run's outer third each end's wall
// is, left and right (0: the largest; 1: the next, another step).
struct SilhouetteScale {
  double floor = 0.0, rise = 0.0;
  int wall_rank[2] = {0, 0};
};

// The bead at the silhouette of the bead around `center` in w; held: the
// layer's shape (nullptr: its aspect and exponent solved too); start_place:
// where the row before's free shape placed its ends (Silhouette::end_place;
// nullptr: none).
// nullopt where the run around the centre is too short, or either end is
// no wall (the gain rises by less than `rise` there, or the ellipse placed
// stands on the surface below by less at its end: the bead's side meets
// the surface below, nothing to place it by).
// free (where given): with no shape held, the families tried, and what
// the solve found where it placed none.
// walls_unsolved: set where both ends showed walls but no free shape its
// top solves stands over them by more than the rise and what an end
// anywhere in its cell could make of a bead lying on the surface (at 30 um
// of noise on tamped beads 2 mm high, b solved 3.1 mm for 1.0, a superellipse
// boxier than the bead, the widest point a mm under the walls' tops; on
// pressed ellipses seen at points 0.2 mm apart, walls of about 0.55 mm under
// the rise's 0.3 and the cells' 0.38); family_log_ratio: that solve's.
struct FreeSolve {
  bool stadium_only = false;  // the stadium alone tried (part/layer_grooves.h: a layer's evidence)
  bool walls_unsolved = false;
  double family_log_ratio = NAN;
};
std::optional<Silhouette> AtSilhouette(const Window& w, double center, const SilhouetteScale& scale,
                                       const PooledShape* held, const double* start_place = nullptr,
                                       FreeSolve* free = nullptr);

// What a top's miss is judged by (TopTolerance).
struct TopScale {
  double noise_mm, height, spacing;
  double Over(const Silhouette& s) const;  // its top's RMS over the tolerance
};

// The bead at its silhouette, its walls the largest rises at its ends
// (`largest`); where its top misses the shape placed there by over
// kTopOffNoise tolerances, the next rise at either end or both whose
// largest steps over a cliff (Silhouette::over_cliff), the least miss
// within them (`other`). (Beside a bead, the wall of the layers below,
// a cliff sampled at points 0.2 mm apart and read at another pass's
// points, left gains of 0.7-1.2 mm past the bead's end: the largest rise
// lay two points out, the shape placed there missed the top by 0.12-0.16
// mm at 10 um of noise in most of a pressed wall's sixth layer, and the
// layer went uncorrected.)
struct Walls {
  std::optional<Silhouette> largest, other;
};
Walls AtTheWalls(const Window& w, double center, SilhouetteScale scale, const PooledShape* pooled,
                 const double* start_place, FreeSolve& free, const TopScale& top);

// The variance the placement adds to the area seen less the groove: each
// end anywhere in its cell (uniform: the range of the difference's change
// over the cell, squared, over 12), z0 (and b) to their least squares'
// covariance, and a held aspect and exponent to their sigmas; gradient: the
// groove's in x0, z0, a and b at s.e, by_exponent its own in the exponent
// (z0 held).
double SilhouetteVariance(const Silhouette& s, const PooledShape* held, const double gradient[4], double by_exponent);

}  // namespace bead::part
