#include "libbead/part/least_squares.h"

#include <algorithm>

namespace bead::part {
namespace {

Eigen::MatrixXd Jacobian(const LeastSquares& problem, const Eigen::VectorXd& p, const Eigen::VectorXd& r) {
  Eigen::MatrixXd J(r.size(), p.size());
  Eigen::VectorXd moved = p, rm(r.size());
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    const double step = 1e-5 * std::max(1.0, std::abs(p[i]));
    moved = p;
    moved[i] += step;
    if (problem.keep) problem.keep(moved);
    problem.residuals(moved, rm);
    J.col(i) = (rm - r) / step;
  }
  return J;
}

}  // namespace

LeastSquaresFit Minimise(const LeastSquares& problem, Eigen::VectorXd start, int max_iterations) {
  LeastSquaresFit fit;
  if (problem.keep) problem.keep(start);
  fit.p = std::move(start);
  Eigen::VectorXd r;
  problem.residuals(fit.p, r);
  fit.rss = r.squaredNorm();
  double lambda = 1e-3;
  bool converged = false;
  Eigen::VectorXd trial_r(r.size());
  for (int it = 0; it < max_iterations && !converged; ++it) {
    fit.J = Jacobian(problem, fit.p, r);
    const Eigen::MatrixXd JtJ = fit.J.transpose() * fit.J;
    const Eigen::VectorXd g = fit.J.transpose() * r;
    bool better = false;
    for (int tries = 0; tries < 8 && !better; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * (JtJ.diagonal().array() + 1e-12).matrix();
      Eigen::VectorXd trial = fit.p + A.ldlt().solve(-g);
      if (problem.keep) problem.keep(trial);
      problem.residuals(trial, trial_r);
      const double rss = trial_r.squaredNorm();
      if (std::isfinite(rss) && rss < fit.rss) {
        converged = fit.rss - rss < 1e-7 * fit.rss;
        fit.p = std::move(trial), r = trial_r, fit.rss = rss;
        lambda = std::max(lambda * 0.3, 1e-9), better = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!better) break;
  }
  fit.J = Jacobian(problem, fit.p, r);
  return fit;
}

}  // namespace bead::part
