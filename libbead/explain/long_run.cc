#include "libbead/explain/long_run.h"

#include <algorithm>
#include <cmath>

namespace bead::explain {

int AndrewsBandwidth(const Eigen::MatrixXd& g) {
  const Eigen::Index T = g.rows();
  if (T < 3) return 0;
  double numerator = 0, denominator = 0;
  for (Eigen::Index c = 0; c < g.cols(); ++c) {
    const Eigen::VectorXd x = g.col(c).array() - g.col(c).mean();
    const double sd = std::sqrt(x.squaredNorm() / static_cast<double>(T));
    if (!(sd > 0)) continue;
    const Eigen::VectorXd z = x / sd;  // each column on the same footing
    const double rho = std::clamp(z.tail(T - 1).dot(z.head(T - 1)) / z.head(T - 1).squaredNorm(), -0.999, 0.999);
    const double s2 = (z.tail(T - 1) - rho * z.head(T - 1)).squaredNorm() / static_cast<double>(T);
    numerator += 4 * rho * rho * s2 * s2 / (std::pow(1 - rho, 6) * std::pow(1 + rho, 2));
    denominator += s2 * s2 / std::pow(1 - rho, 4);
  }
  if (!(denominator > 0)) return 0;
  const double lag = 1.1447 * std::cbrt(numerator / denominator * static_cast<double>(T));
  return static_cast<int>(std::clamp(lag, 0.0, static_cast<double>(T / 4)));
}

Eigen::MatrixXd LongRunCovariance(const Eigen::MatrixXd& g, int lag) {
  const Eigen::Index n = g.rows();
  Eigen::MatrixXd omega = g.transpose() * g;
  for (int l = 1; l <= lag && l < n; ++l) {
    const Eigen::MatrixXd gamma = g.bottomRows(n - l).transpose() * g.topRows(n - l);
    omega += (1.0 - l / (lag + 1.0)) * (gamma + gamma.transpose());
  }
  return omega;
}

Eigen::MatrixXd PrewhitenedLongRunCovariance(const Eigen::MatrixXd& g, int* lag) {
  const Eigen::Index n = g.rows(), p = g.cols();
  if (n < 3 * p + 3) return LongRunCovariance(g, *lag = AndrewsBandwidth(g));
  // VAR(1) g_t = A g_{t-1} + v_t by least squares.
  const Eigen::MatrixXd x = g.topRows(n - 1), y = g.bottomRows(n - 1);
  Eigen::MatrixXd a = x.colPivHouseholderQr().solve(y).transpose();  // y' = A x'
  // Andrews and Monahan cap the VAR's eigenvalues below 1 (0.97): a unit
  // root would make (I - A)^-1 explode.
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::VectorXd sv = svd.singularValues();
  for (Eigen::Index i = 0; i < sv.size(); ++i) sv(i) = std::min(sv(i), 0.97);
  a = svd.matrixU() * sv.asDiagonal() * svd.matrixV().transpose();
  const Eigen::MatrixXd v = y - x * a.transpose();
  *lag = AndrewsBandwidth(v);
  const Eigen::MatrixXd omega_v = LongRunCovariance(v, *lag) * (static_cast<double>(n) / static_cast<double>(n - 1));
  const Eigen::MatrixXd recolour = (Eigen::MatrixXd::Identity(p, p) - a).inverse();
  return recolour * omega_v * recolour.transpose();
}

Eigen::MatrixXd Scores(const Eigen::MatrixXd& J, const std::vector<double>& e) {
  Eigen::MatrixXd g(J.rows(), J.cols());
  for (Eigen::Index t = 0; t < J.rows(); ++t) {
    const double r = e[static_cast<std::size_t>(t)];
    g.row(t) = J.row(t) * (std::isfinite(r) ? r : 0.0);
  }
  return g;
}

double VarianceAlong(const std::vector<double>& x, const std::vector<double>& e) {
  Eigen::MatrixXd J(static_cast<Eigen::Index>(x.size()), 1);
  double xx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    J(static_cast<Eigen::Index>(i), 0) = std::isfinite(x[i]) ? x[i] : 0.0;
    xx += J(static_cast<Eigen::Index>(i), 0) * J(static_cast<Eigen::Index>(i), 0);
  }
  const Eigen::MatrixXd g = Scores(J, e);
  return xx > 0 ? LongRunCovariance(g, AndrewsBandwidth(g))(0, 0) / xx : 0.0;
}

}  // namespace bead::explain
