// What the hidden groove's estimates share (part/hidden_groove.h): the
// ellipse a wall's bead is taken to be, and the points around the bead with
// the surface below under each.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "libbead/part/superellipse.h"

namespace bead::part {

// The bead: centre (x0, z0), semi-axes a across, b up, and its exponent
// (part/superellipse.h: 2 the ellipse).
struct Ellipse {
  double x0 = 0.0, z0 = 0.0, a = 1.0, b = 1.0, p = 2.0;
  // Half its height at x (0 off it; the ellipse's by its square root, two
  // powers' time).
  double Half(double x) const {
    const double u = (x - x0) / a;
    if (!(std::abs(u) < 1.0)) return 0.0;
    return b * (p == 2.0 ? std::sqrt(1.0 - u * u) : SuperellipseS(u, p));
  }
  double& operator[](std::size_t i) { return i == 0 ? x0 : i == 1 ? z0 : i == 2 ? a : b; }
  double operator[](std::size_t i) const { return i == 0 ? x0 : i == 1 ? z0 : i == 2 ? a : b; }
};

// The layer's beads' shape, pooled (part/layer_grooves.h): the median aspect
// b / a and exponent of the free placements and fits on its first profiles,
// each with its median's standard error (one material, one process: the
// wheel's pooled occlusion carried over). Held, it leaves each profile its
// bead's place, depth and size. A fit (no silhouette) holds the aspect,
// and the exponent where it is not an ellipse's. correlation: between the
// aspect's and the exponent's errors, as the rows placed at their
// silhouettes vary together (a bead solved boxier is solved taller or
// flatter with it: the two pooled errors move the groove together, not
// apart).
struct PooledShape {
  double aspect = NAN, aspect_sigma = 0.0;
  double exponent = 2.0, exponent_sigma = 0.0;
  double correlation = 0.0;
  // Whether the profiler averages over a footprint: more than half the
  // rows placed at their walls had an end whose wall holds a point between
  // the surface below and the top (a mix; part/silhouette_top.h: OnTheTop).
  // Its points then integrate a wall wherever it lies: a mixed end's cell
  // stays its wall's (part/silhouette.cc), and what the spot leaves in the
  // rows' shapes is held whole (below).
  bool footprint = false;
  // aspect_sigma's two parts, in quadrature: what the rows' spread (or the
  // floor their ends and grid set) leaves, and what the footprint leaves
  // (Silhouette::aspect_mixed_var, the same in every row: more rows do not
  // shrink it).
  double aspect_rows_sigma = 0.0, aspect_footprint_sigma = 0.0;
  // false: too few rows were placed at their walls to solve the exponent;
  // the ellipse's is held, by assumption.
  bool exponent_solved = false;
  // Where not -1: too few were, and the exponent is that earlier layer's,
  // the last one solved (one material, one process), carried.
  int64_t exponent_layer = -1;
  // The rows whose aspects were pooled.
  std::size_t rows = 0;
  // The median over those rows of their tops' RMS about the shape over
  // their tolerance, the noise, a share of the height and what the points'
  // spacing leaves (part/hidden_groove.h: TopTolerance, TopSamplingMm,
  // OutlineMisfit::kTopOff).
  double top_noise = NAN;
  // Most of the layer's rows placed at their walls had an end the top put
  // off its wall's cell (part/hidden_groove.h: OutlineMisfit::kEndsOff).
  bool ends_off = false;
  // Where not -1: the verdict is that earlier layer's, carried with its
  // exponent (this layer shows too few walls to judge its own).
  int64_t ends_off_layer = -1;
  // Of the rows estimated before the pool was formed (`estimated`), those
  // whose ends showed walls but whose tops solved no shape standing over
  // them (HiddenGroove::walls_unsolved): where most are, the exponent is
  // not solved because the tops and walls do not pin the shape (noise, the
  // ends' cells), not because the beads do not overhang.
  std::size_t estimated = 0, walls_unsolved = 0;
  // Whether the rows were placed with the stadium's family alone, most
  // of their walls unsolved otherwise and their evidence favouring it
  // (part/layer_grooves.h: RetryAsStadiums).
  bool stadium_by_evidence = false;
  bool ShapeUnpinned() const { return !exponent_solved && 2 * walls_unsolved > estimated; }
  // Whether the exponent solved is not an ellipse's: beyond two of its
  // sigmas from 2 (`bead measure` says "an ellipse, within two sigmas"
  // otherwise). Fits (no silhouette) then hold it; else an ellipse's.
  bool NotAnEllipse() const {
    return exponent_solved && std::abs(exponent - EllipseOf(exponent)) > 2.0 * exponent_sigma;
  }
  // A stadium's pool (part/superellipse.h: a tamped bead, its height held
  // by the tamper, widened by more flow, not heightened): its half-height b
  // and the width of its ends' arcs c a, mm (the rows' medians; the sigmas
  // the aspect's and exponent's at the rows' median half-width). Held, each
  // row's aspect and corner share follow from its own half-width: half its
  // width as measured (part/added_bead.h) less width_excess_mm, the rows'
  // median of that less the half-width placed at the walls (the width's
  // crossing of the edge floor lies beyond a wall's foot by part of a
  // spacing: b and c a pooled over the width's half were 0.7-0.9 % high).
  // NaN: not a stadium's.
  double half_height_mm = NAN, corner_mm = NAN, half_height_sigma_mm = 0.0, corner_sigma_mm = 0.0;
  double width_excess_mm = 0.0;
  bool Tamped() const { return NotAnEllipse() && IsStadium(exponent) && std::isfinite(half_height_mm); }
  // The pool held for a bead `width` wide: a tamped one's aspect and corner
  // share at its half-width (their sigmas with them), any other's as it is.
  PooledShape AtWidth(double width) const {
    PooledShape at = *this;
    const double a = 0.5 * width - width_excess_mm;
    if (!Tamped() || !(a > 0.0)) return at;
    at.aspect = half_height_mm / a, at.exponent = -std::clamp(corner_mm / a, 0.1, 1.0);
    at.aspect_sigma = half_height_sigma_mm / a, at.exponent_sigma = corner_sigma_mm / a;
    at.held_b_mm = half_height_mm;
    return at;
  }
  // Held at a row's width (AtWidth), a tamped bead's half-height, held as
  // it is wherever the bead's ends are placed (the tamper holds it): the
  // aspect at a half-width a placed is held_b_mm / a (any other shape's:
  // the aspect held). (Held as the aspect at the width measured, b followed
  // the ends placed, and the width measured besides: where gains past a
  // bead's end, a cliff read at another pass's points, widened the width
  // by 0.8 mm, b came out 0.88 mm for 1.0 and the bead placed floated over
  // the one below, its row uncorrected.)
  double held_b_mm = NAN;
  double AspectAt(double a) const { return std::isfinite(held_b_mm) ? held_b_mm / a : aspect; }
  // Whether the aspect (and the tops' miss) is pooled over the rows placed
  // at their walls alone: the layer's own exponent is not an ellipse's (a
  // fit's aspect is an ellipse's, not that shape's, until it is pooled).
  bool AspectAtWalls() const { return NotAnEllipse() && exponent_layer < 0; }
};

// The points around the bead with the surface below under each.
struct Window {
  std::vector<double> x, z, old;  // x increasing
  // bare[j]: the sum of (old - z)^2 over the points before j, the residual
  // each has where the ellipse does not reach it.
  std::vector<double> bare;
  void Close() {
    bare.assign(x.size() + 1, 0.0);
    for (std::size_t j = 0; j < x.size(); ++j) bare[j + 1] = bare[j] + (old[j] - z[j]) * (old[j] - z[j]);
  }
  double Gain(std::size_t j) const { return z[j] - old[j]; }
};

}  // namespace bead::part
