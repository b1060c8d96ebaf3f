// The Ceres settings our small dense fits share (pin chords, bead shapes,
// transfer functions): dense QR, silent, bounded iterations. Header-only;
// only targets that link Ceres include it (bead::core stays Ceres-free).
#pragma once

#include <ceres/ceres.h>

namespace bead::fit {

inline ceres::Solver::Options QuietDenseOptions(int max_iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.logging_type = ceres::SILENT;
  return options;
}

}  // namespace bead::fit
