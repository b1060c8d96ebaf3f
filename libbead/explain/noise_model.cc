#include "libbead/explain/noise_model.h"

#include <algorithm>
#include <cmath>

namespace bead::explain {
namespace {

// Biased autocovariances c_0..c_p of the centred series (Yule-Walker's,
// which keep the Toeplitz matrix positive definite).
std::vector<double> Autocovariance(const std::vector<double>& x, int p) {
  const std::size_t n = x.size();
  double mean = 0;
  for (double v : x) mean += v / static_cast<double>(n);
  std::vector<double> c(static_cast<std::size_t>(p) + 1, 0.0);
  for (std::size_t k = 0; k < c.size(); ++k)
    for (std::size_t t = k; t < n; ++t) c[k] += (x[t] - mean) * (x[t - k] - mean) / static_cast<double>(n);
  return c;
}

}  // namespace

ArNoise FitArNoise(const std::vector<double>& residual, int max_order) {
  std::vector<double> x;
  for (double v : residual)
    if (std::isfinite(v)) x.push_back(v);
  ArNoise best;
  const std::size_t n = x.size();
  if (n < 8) return best;
  const int p_max = std::clamp(max_order, 0, static_cast<int>(n / 10));
  const std::vector<double> c = Autocovariance(x, p_max);
  best.variance = best.innovation_var = c[0];
  if (!(c[0] > 0)) return best;
  // Levinson-Durbin: the order-k coefficients from the order-(k-1) ones.
  std::vector<double> a, prev;
  double err = c[0];
  const double nn = static_cast<double>(n);
  double best_aic = nn * std::log(err);
  for (int k = 1; k <= p_max; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    double acc = c[uk];
    for (std::size_t j = 1; j < uk; ++j) acc -= a[j - 1] * c[uk - j];
    const double reflection = acc / err;
    if (!(std::abs(reflection) < 1.0)) break;
    prev = a;
    a.assign(uk, 0.0);
    for (std::size_t j = 1; j < uk; ++j) a[j - 1] = prev[j - 1] - reflection * prev[uk - j - 1];
    a[uk - 1] = reflection;
    err *= 1.0 - reflection * reflection;
    const double aic = nn * std::log(err) + 2.0 * k;
    if (aic < best_aic) best_aic = aic, best.a = a, best.innovation_var = err;
  }
  return best;
}

Eigen::MatrixXd ApplyCovariance(const ArNoise& m, const Eigen::MatrixXd& J) {
  const auto n = static_cast<std::size_t>(J.rows());
  const std::size_t p = m.a.size();
  Eigen::MatrixXd out(J.rows(), J.cols());
  std::vector<double> y(n), z(n);
  for (Eigen::Index c = 0; c < J.cols(); ++c) {
    for (std::size_t t = n; t-- > 0;) {  // y = A^-T x: y_t = x_t + sum_k a_k y_{t+k}
      const double x = J(static_cast<Eigen::Index>(t), c);
      double v = std::isfinite(x) ? x : 0.0;
      for (std::size_t k = 1; k <= p && t + k < n; ++k) v += m.a[k - 1] * y[t + k];
      y[t] = v;
    }
    for (std::size_t t = 0; t < n; ++t) {  // z = A^-1 y: z_t = y_t + sum_k a_k z_{t-k}
      double v = y[t];
      for (std::size_t k = 1; k <= p && k <= t; ++k) v += m.a[k - 1] * z[t - k];
      z[t] = v;
      out(static_cast<Eigen::Index>(t), c) = v * m.innovation_var;
    }
  }
  return out;
}

}  // namespace bead::explain
