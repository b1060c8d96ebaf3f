// The long-run covariance of a score series, for intervals that hold on a
// residual as coloured as a flow model leaves (lag-one correlation 0.98 at
// 200 Hz). A least-squares estimate theta = (J'J)^-1 J'y has the covariance
//   (J'J)^-1 Omega (J'J)^-1,   Omega = the long-run covariance of g_t = J_t e_t
// (the sandwich, White 1980), Omega estimated by Newey and West's kernel
// sum (Econometrica 55, 1987, eq. 2: the autocovariances of g to lag L with
// Bartlett weights 1 - l / (L + 1), positive semi-definite) at Andrews'
// data-dependent bandwidth (Econometrica 59, 1991, eq. 6.2 and 6.4, the AR(1)
// plug-in for the Bartlett kernel: L = 1.1447 (alpha(1) T)^(1/3),
//   alpha(1) = sum 4 rho^2 s^4 / ((1 - rho)^6 (1 + rho)^2) / sum s^4 / (1 - rho)^4
// over the score's columns, each an AR(1) with coefficient rho and
// innovation variance s). On a white residual Omega is s2 J'J and the
// usual covariance comes back.
//
// Why not a parametric noise model: an AR model fitted to the residual
// (Box-Jenkins' H = 1 / A) was tried first; BIC picks orders 3-4, which
// smear the residual's strong low-frequency power over the band where the
// regressors live, and its intervals came out 1.5-2x wider than the spread
// of 40 twin runs' estimates (all 40 covered). The kernel sum weighs the
// residual's colour by each regressor's own, as the sandwich must.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace bead::explain {

// Andrews' Bartlett bandwidth for the columns of g (T x P), within [0, T / 4].
int AndrewsBandwidth(const Eigen::MatrixXd& g);

// Newey-West's Omega for the scores g (T x P) at lag L.
Eigen::MatrixXd LongRunCovariance(const Eigen::MatrixXd& g, int lag);

// Andrews and Monahan's prewhitened estimate (Econometrica 60, 1992): the
// scores through a VAR(1), its innovations' Omega at their own Andrews
// bandwidth, recoloured by (I - A)^-1.
Eigen::MatrixXd PrewhitenedLongRunCovariance(const Eigen::MatrixXd& g, int* lag);

// The scores J_t e_t for a Jacobian J (rows as e) and a residual e (NaN as 0).
Eigen::MatrixXd Scores(const Eigen::MatrixXd& J, const std::vector<double>& e);

// x' Omega_x x / x' x for the single direction x: the variance the residual
// has along it, counting its colour (white: the residual's variance).
double VarianceAlong(const std::vector<double>& x, const std::vector<double>& e);

}  // namespace bead::explain
