// The colour of a residual: an autoregressive noise model
//   e_t = a_1 e_{t-1} + ... + a_p e_{t-p} + w_t,   w white with variance s2,
// the noise part H(q) = 1 / A(q) of a Box-Jenkins model (Ljung, System
// Identification, 1999, eq. 4.40; MATLAB's bj and ar) fitted to the
// residual the process model leaves: Yule-Walker equations solved by the
// Levinson-Durbin recursion (Ljung eq. 7.125 ff.), so A(q) is minimum
// phase. The order by AIC up to min(100, n / 10): a residual is no finite
// AR, and for an AR(infinity) AIC's choice is the asymptotically efficient
// one (Shibata, Ann. Statist. 8, 1980, section 4); BIC's smaller orders
// made the intervals of a delay 25 % too narrow on the twin.
//
// What the loop's intervals use it for (parameter_covariance.h): a
// least-squares estimate theta = (J'J)^-1 J'y has, under noise of
// covariance Sigma, the covariance (J'J)^-1 J' Sigma J (J'J)^-1 (the
// sandwich; White, Econometrica 48, 1980, with Sigma parametric), and with
// the AR model Sigma = s2 A^-1 A^-T, A the lower-triangular Toeplitz matrix
// of [1, -a_1, ..., -a_p]: Sigma x is two recursive filters, backward and
// forward. A white residual gives s2 (J'J)^-1 back. Samples are taken in
// their order (a profile's flow at 200 Hz with a few dropped profiles is
// nearly even).
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace bead::explain {

struct ArNoise {
  std::vector<double> a;        // a_1..a_p
  double innovation_var = 0.0;  // s2
  double variance = 0.0;        // the residual's own
};

// NaN samples are skipped.
ArNoise FitArNoise(const std::vector<double>& residual, int max_order = 100);

// Sigma J for the model, column by column (J's rows sampled like the
// residual the model was fitted on; NaN taken as 0).
Eigen::MatrixXd ApplyCovariance(const ArNoise& noise, const Eigen::MatrixXd& J);

}  // namespace bead::explain
