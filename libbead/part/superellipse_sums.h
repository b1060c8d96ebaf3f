// A fitted bead's residual sums where its shape is a superellipse of
// exponent p != 2 (a layer's pooled shape that is not an ellipse, held in
// a fit: part/hidden_groove.cc); the ellipse's are part_kernel.h's.
#pragma once

#include <cstddef>

#include "libbead/part/groove_window.h"
#include "libbead/part/part_kernel.h"

namespace bead::part {

// Over the window's points [lo, hi): the residuals' sum of squares and the
// normal equations of x0, z0, a and b (b's column 0 where `aspect` is
// finite: b = aspect a held), as part_kernel.h's ellipse gives them.
EllipseSums SuperellipseSums(const Window& w, std::size_t lo, std::size_t hi, const Ellipse& e, double aspect);

}  // namespace bead::part
