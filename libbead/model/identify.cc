#include "libbead/model/identify.h"

#include <ceres/ceres.h>

#include "libbead/fit/solver_options.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>

#include "libbead/core/error.h"
#include "libbead/series/interpolate.h"

namespace bead::model {
namespace {

TransferFunction FromTheta(const std::vector<double>& theta, int n, int m, double delay) {
  TransferFunction tf;
  tf.den.assign(1, 1.0);
  for (int k = 0; k < n; ++k) tf.den.push_back(theta[static_cast<std::size_t>(k)]);
  for (int k = 0; k <= m; ++k) tf.num.push_back(theta[static_cast<std::size_t>(n + k)]);
  tf.delay_s = std::max(0.0, delay);
  return tf;
}

// theta = (a1..an, b0..bm) of a monic denominator.
std::vector<double> ToTheta(const TransferFunction& tf, int n, int m) {
  std::vector<double> theta;
  for (int k = 1; k <= n; ++k) theta.push_back(tf.den[static_cast<std::size_t>(k)] / tf.den[0]);
  for (int k = 0; k <= m; ++k) theta.push_back(tf.num[static_cast<std::size_t>(k)] / tf.den[0]);
  return theta;
}

double Loss(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u,
            const std::vector<double>& y) {
  const auto yhat = Simulate(tf, t, u);
  double ss = 0;
  for (std::size_t i = 0; i < y.size(); ++i) ss += (y[i] - yhat[i]) * (y[i] - yhat[i]);
  return std::isfinite(ss) ? ss / y.size() : INFINITY;
}

bool Stable(const TransferFunction& tf, std::vector<double>* re = nullptr, std::vector<double>* im = nullptr) {
  const int n = tf.poles();
  if (n == 0) return true;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) companion(0, k) = -tf.den[static_cast<std::size_t>(k + 1)] / tf.den[0];
  for (int k = 1; k < n; ++k) companion(k, k - 1) = 1.0;
  const Eigen::VectorXcd roots = companion.eigenvalues();
  bool stable = true;
  for (int k = 0; k < n; ++k) {
    stable = stable && roots(k).real() < 0;
    if (re) re->push_back(roots(k).real());
    if (im) im->push_back(roots(k).imag());
  }
  return stable;
}

// An unstable start made stable the way MATLAB's tfest does its initial
// estimates: each pole in the right half plane reflected into the left
// (its real part negated), the monic denominator rebuilt from the poles.
// Returns false when the start was stable already.
bool ReflectUnstablePoles(TransferFunction& tf) {
  std::vector<double> re, im;
  if (Stable(tf, &re, &im)) return false;
  std::vector<std::complex<double>> poly = {1.0};
  for (std::size_t k = 0; k < re.size(); ++k) {
    const std::complex<double> root(re[k] < 0 ? re[k] : -std::max(std::abs(re[k]), 1e-6), im[k]);
    std::vector<std::complex<double>> next(poly.size() + 1, 0.0);
    for (std::size_t i = 0; i < poly.size(); ++i) {
      next[i] += poly[i];
      next[i + 1] -= root * poly[i];
    }
    poly = next;
  }
  const double lead = tf.den[0];
  for (std::size_t i = 0; i < tf.den.size(); ++i) tf.den[i] = lead * poly[i].real();
  return true;
}

// Young's state-variable filter: linear least squares for the coefficients.
std::optional<std::vector<double>> SvfStart(const std::vector<double>& t, const std::vector<double>& u,
                                            const std::vector<double>& y, int n, int m, double delay, double lambda,
                                            double dt) {
  const std::size_t N = t.size();
  // Filter F(s) = lambda^(n+1) / (s + lambda)^(n+1), and s^k F(s), k <= n:
  // one order above the model, so even s^n F(s) falls off at high frequency
  // and the held samples' staircase does not leak into the derivatives.
  std::vector<double> den = {1.0};
  for (int k = 0; k <= n; ++k) {
    std::vector<double> next(den.size() + 1, 0.0);
    for (std::size_t i = 0; i < den.size(); ++i) {
      next[i] += den[i];
      next[i + 1] += lambda * den[i];
    }
    den = next;
  }
  auto filtered = [&](const std::vector<double>& x, int k, double d) {
    std::vector<double> num(static_cast<std::size_t>(k) + 1, 0.0);
    num[0] = std::pow(lambda, n + 1);
    return Simulate(TransferFunction{num, den, d}, t, x);
  };
  std::vector<std::vector<double>> yf, uf;
  for (int k = 0; k <= n; ++k) yf.push_back(filtered(y, k, 0.0));
  // Held between samples, y lags the continuous output by about dt / 2;
  // the input is truly held. Delaying the input's filters by dt / 2 as well
  // keeps the two consistent.
  for (int k = 0; k <= m; ++k) uf.push_back(filtered(u, k, delay + dt / 2));
  // s^n y = -a1 s^(n-1) y - ... - an y + b0 s^m u + ... + bm u
  Eigen::MatrixXd a(N, n + m + 1);
  Eigen::VectorXd b(N);
  for (std::size_t i = 0; i < N; ++i) {
    for (int k = 0; k < n; ++k) a(static_cast<long>(i), k) = -yf[static_cast<std::size_t>(n - 1 - k)][i];
    for (int k = 0; k <= m; ++k) a(static_cast<long>(i), n + k) = uf[static_cast<std::size_t>(m - k)][i];
    b(static_cast<long>(i)) = yf[static_cast<std::size_t>(n)][i];
  }
  const Eigen::VectorXd theta = a.colPivHouseholderQr().solve(b);
  if (!theta.allFinite()) return std::nullopt;
  return std::vector<double>(theta.data(), theta.data() + theta.size());
}

// y - simulated y for the coefficients in params[0], at a fixed delay.
struct SimulationError {
  const std::vector<double>& t;
  const std::vector<double>& u;
  const std::vector<double>& y;
  int n, m;
  double delay;
  bool operator()(double const* const* params, double* residuals) const {
    const std::vector<double> theta(params[0], params[0] + n + m + 1);
    const auto yhat = Simulate(FromTheta(theta, n, m, delay), t, u);
    for (std::size_t i = 0; i < y.size(); ++i) residuals[i] = y[i] - yhat[i];
    return true;
  }
};

}  // namespace

IdentifiedModel IdentifyTransferFunction(const std::vector<double>& t, const std::vector<double>& u,
                                         const std::vector<double>& y, const IdentifyOptions& o) {
  IdentifiedModel out;
  const int n = o.poles, m = o.zeros;
  if (n < 1 || m < 0 || m > n) {
    out.reason = "need poles >= 1 and 0 <= zeros <= poles";
    return out;
  }
  if (t.size() != u.size() || t.size() != y.size() || t.size() < static_cast<std::size_t>(4 * (n + m + 2))) {
    out.reason = "too few samples for this model";
    return out;
  }
  const double dt = MedianStep(t);
  const double lambda = o.filter_rad_s > 0 ? o.filter_rad_s : 2 * M_PI / (20 * dt);

  // Delay grid, each scored by its SVF start's simulation error.
  std::vector<double> delays;
  if (o.delay_s)
    delays.push_back(*o.delay_s);
  else
    for (int k = 0; k < o.delay_grid; ++k) delays.push_back(o.max_delay_s * k / std::max(1, o.delay_grid - 1));
  // Score each grid delay by its SVF start; refine the best few (the loss
  // is multi-modal in the delay and the SVF start is biased by noise).
  struct Candidate {
    double loss, delay;
    std::vector<double> theta;
  };
  std::vector<Candidate> candidates;
  for (double d : delays) {
    const auto theta = SvfStart(t, u, y, n, m, d, lambda, dt);
    if (!theta) continue;
    TransferFunction tf = FromTheta(*theta, n, m, d);
    std::vector<double> start = *theta;
    if (ReflectUnstablePoles(tf)) start = ToTheta(tf, n, m);
    if (!Stable(tf)) continue;
    candidates.push_back({Loss(tf, t, u, y), d, start});
  }
  if (candidates.empty()) {
    out.reason = "no stable starting model (try other orders, or a fixed --delay)";
    return out;
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.loss < b.loss; });
  candidates.resize(std::min<std::size_t>(candidates.size(), 3));
  // Output error at a fixed delay, from a start; returns the loss (inf: unusable).
  auto refit = [&](std::vector<double>& theta, double delay) {
    auto* cost = new ceres::DynamicNumericDiffCostFunction<SimulationError, ceres::CENTRAL>(
        new SimulationError{t, u, y, n, m, delay});
    cost->AddParameterBlock(n + m + 1);
    cost->SetNumResiduals(static_cast<int>(y.size()));
    ceres::Problem problem;
    problem.AddResidualBlock(cost, nullptr, theta.data());
    const ceres::Solver::Options so = fit::QuietDenseOptions(o.max_iterations);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    const TransferFunction tf = FromTheta(theta, n, m, delay);
    if (!summary.IsSolutionUsable() || !Stable(tf)) return static_cast<double>(INFINITY);
    return Loss(tf, t, u, y);
  };
  double refined_loss = candidates[0].loss;
  std::vector<double> best_theta = candidates[0].theta;
  double best_delay = candidates[0].delay;
  for (const Candidate& c : candidates) {
    std::vector<double> theta = c.theta;
    const double loss = refit(theta, c.delay);
    if (loss < refined_loss) refined_loss = loss, best_theta = theta, best_delay = c.delay;
  }
  if (!o.delay_s) {
    // The loss is sharp in the delay: golden-section search over +-1 sample
    // (bounded by [0, max_delay]), the coefficients re-fitted at each trial.
    const double phi = (std::sqrt(5.0) - 1) / 2;
    double a = std::max(0.0, best_delay - dt), b = std::min(o.max_delay_s, best_delay + dt);
    auto trial = [&](double d, std::vector<double>& theta) {
      theta = best_theta;
      return refit(theta, d);
    };
    std::vector<double> t1, t2;
    double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
    double f1 = trial(x1, t1), f2 = trial(x2, t2);
    for (int it = 0; it < 12; ++it) {
      if (f1 < f2) {
        b = x2, x2 = x1, f2 = f1, t2 = t1;
        x1 = b - phi * (b - a);
        f1 = trial(x1, t1);
      } else {
        a = x1, x1 = x2, f1 = f2, t1 = t2;
        x2 = a + phi * (b - a);
        f2 = trial(x2, t2);
      }
    }
    if (std::min(f1, f2) < refined_loss) {
      refined_loss = std::min(f1, f2);
      best_delay = f1 < f2 ? x1 : x2;
      best_theta = f1 < f2 ? t1 : t2;
    }
  }
  const TransferFunction refined = FromTheta(best_theta, n, m, best_delay);
  out.tf = refined;
  Stable(out.tf, &out.poles_real, &out.poles_imag);
  out.parameters = n + m + 1 + (o.delay_s ? 0 : 1);
  const auto yhat = Simulate(out.tf, t, u);
  out.fit_percent = FitPercent(y, yhat);
  std::vector<double> e(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) e[i] = y[i] - yhat[i];
  out.criteria = CriteriaFromResiduals(e, out.parameters);
  out.ok = true;
  return out;
}

double ValidateFitPercent(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u,
                          const std::vector<double>& y) {
  return FitPercent(y, Simulate(tf, t, u));
}

std::vector<OrderRow> OrderTable(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                                 const std::vector<double>& tv, const std::vector<double>& uv,
                                 const std::vector<double>& yv, IdentifyOptions o) {
  std::vector<OrderRow> rows;
  for (int p = 1; p <= 3; ++p)
    for (int z = 0; z <= std::min(p, 2); ++z) {  // thesis Table 3: (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2)
      o.poles = p;
      o.zeros = z;
      const IdentifiedModel mdl = IdentifyTransferFunction(t, u, y, o);
      rows.push_back({p, z, mdl.ok ? mdl.fit_percent : NAN, mdl.ok ? ValidateFitPercent(mdl.tf, tv, uv, yv) : NAN,
                      mdl.ok ? mdl.criteria.aicc : NAN, mdl.ok});
    }
  return rows;
}

}  // namespace bead::model
