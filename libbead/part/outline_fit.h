// A bead's outline fitted to the points of its top the sensor sees
// (part/hidden_groove.cc: a row's ellipse, or a superellipse of the
// layer's pooled exponent): Levenberg-Marquardt over x0, z0, a, and b
// unless the layer's aspect is held.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "libbead/part/groove_window.h"

namespace bead::part {

// The parameters fitted: x0, z0, a, and b unless the aspect b / a is held
// (the layer's pooled shape).
struct FitShape {
  double min_a = 0.0;
  double aspect = NAN;  // held where finite
  std::size_t Params() const { return std::isfinite(aspect) ? 3 : 4; }
  void Keep(Ellipse& e) const {
    e.a = std::max(e.a, min_a), e.b = std::isfinite(aspect) ? aspect * e.a : std::max(e.b, 1e-3);
  }
};

// Fits `e` (its exponent held) to the window's points from where it
// stands; returns the residuals' sum of squares, J^T J of the fitted
// parameters in JtJ (its top left).
double FitOutline(const Window& w, Ellipse& e, const FitShape& shape, Eigen::Matrix4d& JtJ);

}  // namespace bead::part
