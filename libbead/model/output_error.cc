#include "libbead/model/output_error.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "libbead/fit/solver_options.h"

namespace bead::model {

std::vector<std::complex<double>> Roots(const std::vector<double>& den) { return PolynomialRoots(den); }

std::vector<double> FromRoots(const std::vector<std::complex<double>>& roots) {
  std::vector<std::complex<double>> poly = {1.0};
  for (const auto& root : roots) {
    std::vector<std::complex<double>> next(poly.size() + 1, 0.0);
    for (std::size_t i = 0; i < poly.size(); ++i) next[i] += poly[i], next[i + 1] -= root * poly[i];
    poly = next;
  }
  std::vector<double> den;
  for (const auto& c : poly) den.push_back(c.real());
  return den;
}

std::vector<double> ToSearch(const std::vector<double>& den, bool real_poles, double slowest) {
  std::vector<std::complex<double>> roots = Roots(den);
  const double floor = std::max(1e-6, slowest);
  for (auto& r : roots) {
    if (!(r.real() < 0)) r = {-std::max(std::abs(r.real()), floor), r.imag()};
    if (std::abs(r) < floor) r *= floor / std::max(std::abs(r), 1e-300);
  }
  if (!real_poles) {
    // Log coefficients: every coefficient of a stable polynomial is
    // positive, and a pole running fast moves them on a log scale.
    const std::vector<double> stable = FromRoots(roots);
    std::vector<double> theta;
    for (std::size_t k = 1; k < stable.size(); ++k) theta.push_back(std::log(std::max(stable[k], 1e-300)));
    return theta;
  }
  std::vector<double> theta;
  for (std::size_t k = 0; k < roots.size(); ++k) {
    double p = std::abs(roots[k]);
    if (std::abs(roots[k].imag()) > 1e-9 * p) p *= roots[k].imag() > 0 ? 0.8 : 1.25;
    theta.push_back(std::log(1.0 / std::max(p, floor)));
  }
  return theta;
}

std::vector<double> FromSearch(const double* theta, int n, bool real_poles) {
  if (!real_poles) {
    std::vector<double> den = {1.0};
    for (int k = 0; k < n; ++k) den.push_back(std::exp(theta[k]));
    return den;
  }
  std::vector<std::complex<double>> roots;
  for (int k = 0; k < n; ++k) roots.emplace_back(-std::exp(-theta[k]), 0.0);
  return FromRoots(roots);
}

namespace {

// The projected output error as a Ceres cost with its own differences:
// absolute steps (forward, 1e-5 in a log coefficient or log time constant;
// central, 2 % of a sample step in the delay), because the residual is
// piecewise smooth in the delay (a kink wherever a switch of the delayed
// input crosses a sample), which a relative step near 0 s, or one far
// below the kinks' spacing, turns into noise. One-sided at the delay's bounds.
class OutputError : public ceres::CostFunction {
 public:
  OutputError(const ProjectionProblem& problem, int n, bool real_poles, std::optional<double> fixed_delay, double dt,
              double lo, double hi, double slowest)
      : problem_(problem),
        n_(n),
        real_poles_(real_poles),
        fixed_delay_(fixed_delay),
        step_delay_(0.02 * dt),
        lo_(lo),
        hi_(hi),
        slowest_(slowest) {
    mutable_parameter_block_sizes()->push_back(n);
    if (!fixed_delay) mutable_parameter_block_sizes()->push_back(1);
    set_num_residuals(static_cast<int>(problem.rows.size()));
  }

  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    std::vector<double> theta(params[0], params[0] + n_);
    const double delay = fixed_delay_ ? *fixed_delay_ : params[1][0];
    if (!Residual(theta, delay, residuals)) return false;
    if (!jacobians) return true;
    const std::size_t R = problem_.rows.size();
    std::vector<double> plus(R), minus(R);
    if (jacobians[0]) {
      // Forward differences (the residual is smooth in these; one
      // projection each), backward where the forward trial is unstable.
      for (int k = 0; k < n_; ++k) {
        const double h = 1e-5;
        std::vector<double> tp = theta;
        tp[static_cast<std::size_t>(k)] += h;
        bool forward = Residual(tp, delay, plus.data());
        if (!forward) {
          tp[static_cast<std::size_t>(k)] -= 2 * h;
          if (!Residual(tp, delay, plus.data())) return false;
        }
        const double step = forward ? h : -h;
        for (std::size_t r = 0; r < R; ++r)
          jacobians[0][r * static_cast<std::size_t>(n_) + static_cast<std::size_t>(k)] =
              (plus[r] - residuals[r]) / step;
      }
    }
    if (!fixed_delay_ && jacobians[1]) {
      const double dp = std::min(delay + step_delay_, hi_), dm = std::max(delay - step_delay_, lo_);
      if (!(dp > dm)) {
        std::fill(jacobians[1], jacobians[1] + R, 0.0);
        return true;
      }
      if (!Residual(theta, dp, plus.data()) || !Residual(theta, dm, minus.data())) return false;
      for (std::size_t r = 0; r < R; ++r) jacobians[1][r] = (plus[r] - minus[r]) / (dp - dm);
    }
    return true;
  }

 private:
  bool Residual(const std::vector<double>& theta, double delay, double* residuals) const {
    const std::vector<double> den = FromSearch(theta.data(), n_, real_poles_);
    if (!HurwitzStable(den)) return false;
    // No pole slower than the longest stretch resolves (see ToSearch).
    for (const auto& r : Roots(den))
      if (std::abs(r) < 0.5 * slowest_) return false;
    const Projection pr = Project(problem_, den, std::max(0.0, delay), true);
    if (!pr.ok) return false;
    std::copy(pr.residual.begin(), pr.residual.end(), residuals);
    return true;
  }

  const ProjectionProblem& problem_;
  int n_;
  bool real_poles_;
  std::optional<double> fixed_delay_;
  double step_delay_, lo_, hi_, slowest_;
};

}  // namespace

Refined Refine(const ProjectionProblem& problem, const IdentifyOptions& o, std::vector<double> theta, double delay,
               double lo, double hi, double dt, double slowest) {
  const int n = o.poles;
  auto* cost = new OutputError(problem, n, o.real_poles, o.delay_s, dt, lo, hi, slowest);
  std::vector<double*> blocks = {theta.data()};
  if (!o.delay_s) blocks.push_back(&delay);
  ceres::Problem cp;
  cp.AddResidualBlock(cost, nullptr, blocks);
  // No bounds on the delay (Ceres meets a bound by a projected line search
  // that stalls here): a negative trial is read as 0 s, and the result is
  // held to the range after.
  ceres::Solver::Options so = fit::QuietDenseOptions(o.max_iterations);
  so.initial_trust_region_radius = 1e2;
  so.function_tolerance = 1e-9;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &cp, &summary);
  Refined r;
  r.theta = theta;
  r.den = FromSearch(theta.data(), n, o.real_poles);
  r.delay = o.delay_s ? *o.delay_s : std::clamp(delay, lo, hi);
  if (!HurwitzStable(r.den)) return r;
  const Projection pr = Project(problem, r.den, r.delay);
  if (pr.ok) r.loss = pr.sse / static_cast<double>(problem.rows.size());
  return r;
}

}  // namespace bead::model
