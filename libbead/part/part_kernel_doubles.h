// The part kernel's loops in doubles (part_kernel_doubles.cc), which
// part_kernel.cc puts in its table; each build's own (BEAD_KERNEL), not
// installed.
#pragma once

#include <cstddef>

#include "libbead/part/part_kernel.h"

namespace bead::part::BEAD_KERNEL {

EllipseSums Ellipse(const double* x, const double* z, const double* old, std::size_t lo, std::size_t hi,
                    const EllipseAt& e);
TopSums5 Top(const double* x, const double* z, std::size_t lo, std::size_t hi, double x0, double per_a,
             const TopTable& table);
void RowsAtPlaces(const double* x, std::size_t n, const RowsAt& rows, double* out);

}  // namespace bead::part::BEAD_KERNEL
