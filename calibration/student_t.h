// Two-sided 95 % quantile of Student's t distribution, t_{0.975, dof}.
#pragma once

namespace bead::calibration {

double StudentT975(int dof);

}  // namespace bead::calibration
