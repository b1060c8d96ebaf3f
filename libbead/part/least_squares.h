// Levenberg-Marquardt on the small dense fits of part/ (the roads' caps,
// part/road_arcs.h; the ellipse over a hidden groove, part/hidden_groove.h):
// forward-difference derivatives (their models have kinks where two
// surfaces meet: a difference across one is the slope of one side), the
// damping raised tenfold on a step that does not lower the residual and
// lowered to 0.3 of itself on one that does; done when a step lowers the
// residual sum of squares by less than 1e-7 of itself (a parameter then
// moves by well under a thousandth of its sigma: the kinks make the last
// steps creep, and 1e-10 spent a fifth of the groove's time on them).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <functional>

namespace bead::part {

struct LeastSquares {
  // The residuals at p, into r (its size the same at every p).
  std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& r)> residuals;
  // p moved back to where it means something (bounds, shared values);
  // empty: every p does.
  std::function<void(Eigen::VectorXd& p)> keep;
};

struct LeastSquaresFit {
  Eigen::VectorXd p;
  Eigen::MatrixXd J;  // the residuals' Jacobian at p
  double rss = INFINITY;
};

LeastSquaresFit Minimise(const LeastSquares& problem, Eigen::VectorXd start, int max_iterations = 80);

}  // namespace bead::part
