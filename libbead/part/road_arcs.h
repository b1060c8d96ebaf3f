// The overlap model of part/roads.h: roads whose tops are caps of one
// shape (superellipses of one aspect and one exponent), laid in order, each
// adding to the surface before it; and its fit.
#pragma once

#include <span>
#include <vector>

namespace bead::part {

// A road's cap over the surface below: apex at (x0, h), on the
// superellipse |u / a|^p + |(z - z0) / (k a)|^p = 1 with z0 = h - k a
// (p = 2, k = 1: a circle's arc; p = 2: an ellipse's; p large: a flat top
// with steep sides). Where z0 > 0 the cap's sides stand on walls down to the
// surface below (a road that leaves no void under its sides).
struct Arc {
  double x0 = 0.0, h = 0.0, a = 0.0, k = 1.0, p = 2.0;
  // The cap's height at x; below 0 off it.
  double At(double x) const;
  // Its footprint on the surface below: where its outline meets it.
  double Chord() const;
};

// The surface after the arcs laid in their order: max(0, arcs...).
double LayeredAt(std::span<const Arc> arcs, double x);

struct ArcFit {
  std::vector<Arc> arcs;
  double rss = 0.0;  // sum of squared residuals, mm^2
  bool ok = false;
};

// The arcs (started at `start`; aspect and exponent the first's) fitted
// to the gain d at x by Levenberg-Marquardt, one aspect and one exponent
// shared by all (the roads of one layer: one material, one process); the
// exponent held where free_exponent is false. min_a: the smallest
// half-width (a few point spacings), min_h: the smallest apex height.
ArcFit FitArcs(std::span<const double> x, std::span<const double> d, std::vector<Arc> start, double min_a, double min_h,
               bool free_exponent);

}  // namespace bead::part
