#include "libbead/model/identify.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "libbead/core/error.h"
#include "libbead/fit/solver_options.h"
#include "libbead/model/projection.h"
#include "libbead/series/interpolate.h"

namespace bead::model {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<std::complex<double>> Roots(const std::vector<double>& den) {
  const int n = static_cast<int>(den.size()) - 1;
  std::vector<std::complex<double>> out;
  if (n < 1) return out;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) companion(0, k) = -den[static_cast<std::size_t>(k + 1)] / den[0];
  for (int k = 1; k < n; ++k) companion(k, k - 1) = 1.0;
  const Eigen::VectorXcd r = companion.eigenvalues();
  for (int k = 0; k < n; ++k) out.push_back(r(k));
  return out;
}

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

// The search's parameters for a denominator: the logs of its coefficients
// (any transfer function), or the log time constants of real poles (a process
// model). A start with poles in the right half plane is reflected into the
// left (as tfest does with its initial estimates); for a process model a
// complex pair becomes two real poles about its natural frequency.
// A pole slower than `slowest` (1 / the longest stretch) is put there: its
// free response would be a ramp the initial state could use as drift.
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
      : problem_(problem), n_(n), real_poles_(real_poles), fixed_delay_(fixed_delay), step_delay_(0.02 * dt), lo_(lo),
        hi_(hi), slowest_(slowest) {
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
          jacobians[0][r * static_cast<std::size_t>(n_) + static_cast<std::size_t>(k)] = (plus[r] - residuals[r]) / step;
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

struct Refined {
  std::vector<double> den, theta;
  double delay = 0.0, loss = kInf;
};

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

// Lag-one correlation of a residual: its effective sample count is
// N (1 - rho) / (1 + rho).
double EffectiveFraction(const std::vector<double>& e) {
  double c0 = 0, c1 = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    c0 += e[i] * e[i];
    if (i) c1 += e[i] * e[i - 1];
  }
  const double rho = std::clamp(c0 > 0 ? c1 / c0 : 0.0, 0.0, 0.99);
  return (1 - rho) / (1 + rho);
}

ProcessForm ToProcessForm(const TransferFunction& tf) {
  ProcessForm f;
  f.K = tf.DcGain();
  f.Td_s = tf.delay_s;
  f.valid = true;
  for (const auto& r : Roots(tf.den)) {
    if (std::abs(r.imag()) > 1e-9 * std::abs(r) || !(r.real() < 0)) f.valid = false;
    f.Tp_s.push_back(-1.0 / r.real());
  }
  f.Tz_s = std::numeric_limits<double>::quiet_NaN();
  const int m = tf.zeros();
  if (m == 0) f.Tz_s = 0.0;
  if (m == 1 && tf.num.back() != 0.0) f.Tz_s = tf.num[tf.num.size() - 2] / tf.num.back();
  if (m > 1) f.valid = false;
  return f;
}

// The fitted rows: inside the segments, y finite, and past the first
// `skip_s` of each segment (its output there depends on input from before
// the segment, which the record does not hold), except where the process
// started at the segment's first sample (nothing acted before it).
ProjectionProblem MakeProblem(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                              const std::vector<Segment>& segments, int zeros, bool offset, bool initial_state,
                              double skip_s) {
  ProjectionProblem p;
  p.t = &t;
  p.u = &u;
  p.y = &y;
  p.segments = segments.empty() ? WholeRecord(t.size()) : segments;
  p.zeros = zeros;
  p.offset = offset;
  p.initial_state = initial_state;
  for (const Segment& s : p.segments)
    for (std::size_t i = s.begin; i < std::min(s.end, t.size()); ++i)
      if (std::isfinite(y[i]) && (s.process_starts || t[i] >= t[s.begin] + skip_s)) p.rows.push_back(i);
  return p;
}

}  // namespace

IdentifiedModel IdentifyTransferFunction(const std::vector<double>& t, const std::vector<double>& u,
                                         const std::vector<double>& y, const IdentifyOptions& o,
                                         const std::vector<Segment>& segments) {
  IdentifiedModel out;
  const int n = o.poles, m = o.zeros;
  if (n < 1 || n > 7 || m < 0 || m > n) {
    out.reason = "need 1 to 7 poles and 0 <= zeros <= poles";
    return out;
  }
  if (t.size() != u.size() || t.size() != y.size()) {
    out.reason = "time, input and output lengths differ";
    return out;
  }
  for (std::size_t i = 0; i < t.size(); ++i)
    if (!std::isfinite(t[i]) || !std::isfinite(u[i]) || (i && !(t[i] > t[i - 1]))) {
      out.reason = "time must increase and time and input be finite (sample " + std::to_string(i) + ")";
      return out;
    }
  // With a state estimated, the first delay-bound of each stretch is left
  // out; from rest, the input before the record is 0 and nothing is.
  const double skip = o.estimate_initial_state ? (o.delay_s ? *o.delay_s : o.max_delay_s) : 0.0;
  const ProjectionProblem problem =
      MakeProblem(t, u, y, segments, m, o.estimate_offset, o.estimate_initial_state, skip);
  int estimated_states = 0;
  for (const Segment& s : problem.segments) estimated_states += o.estimate_initial_state && !s.process_starts ? n : 0;
  const int linear = (m + 1) + (o.estimate_offset ? 1 : 0) + estimated_states;
  if (problem.rows.size() < static_cast<std::size_t>(4 * (n + linear + 1))) {
    out.reason = "too few samples (" + std::to_string(problem.rows.size()) + ") for this model";
    return out;
  }
  const double dt = MedianStep(t);
  const double lambda = o.filter_rad_s > 0 ? o.filter_rad_s : 2 * M_PI / (20 * dt);
  // The slowest pole the data can tell from the initial state's drift: one
  // time constant across the longest stretch.
  double longest = 0;
  for (const Segment& s : problem.segments)
    if (s.end > s.begin) longest = std::max(longest, t[s.end - 1] - t[s.begin]);
  const double slowest = longest > 0 ? 1.0 / longest : 0.0;
  const SvfSignals svf = FilterForSvf(problem, n, lambda, dt);

  // 1. The delay profile: the linear fit at every step of delay.
  DelayProfile& profile = out.delay_profile;
  if (o.delay_s) {
    profile.delay_s = {*o.delay_s};
  } else {
    const int steps = std::max(1, std::min(o.max_profile_points, static_cast<int>(std::floor(o.max_delay_s / dt))));
    for (int k = 0; k <= steps; ++k) profile.delay_s.push_back(o.max_delay_s * k / steps);
  }
  std::vector<std::vector<double>> starts;
  auto run_profile = [&](const SvfSignals& filtered) {
    profile.loss.clear();
    starts.clear();
    for (double d : profile.delay_s) {
      const auto est = SvfDenominator(problem, filtered, d);
      profile.loss.push_back(est ? est.value().equation_loss : kInf);
      starts.push_back(est ? ToSearch(est->den, o.real_poles, slowest) : std::vector<double>{});
    }
  };
  run_profile(svf);
  // Young's filter works best near the system's own band: a second pass
  // with lambda at twice the fastest pole the first pass found at its best
  // delay (when the user gave no lambda), within [lambda / 10, lambda];
  // kept only where it gives a start at some delay.
  if (o.filter_rad_s <= 0) {
    const auto best_k = static_cast<std::size_t>(std::min_element(profile.loss.begin(), profile.loss.end()) - profile.loss.begin());
    if (!starts[best_k].empty()) {
      double fastest = 0;
      for (const auto& r : Roots(FromSearch(starts[best_k].data(), n, o.real_poles))) fastest = std::max(fastest, std::abs(r));
      const double lambda2 = std::clamp(2.0 * fastest, lambda / 10, lambda);
      if (std::isfinite(lambda2) && lambda2 < 0.8 * lambda) {
        const auto first_loss = profile.loss;
        const auto first_starts = starts;
        run_profile(FilterForSvf(problem, n, lambda2, dt));
        if (std::none_of(profile.loss.begin(), profile.loss.end(), [](double l) { return std::isfinite(l); })) {
          profile.loss = first_loss;
          starts = first_starts;
        }
      }
    }
  }
  // 2. Basins: local minima of the profile, each spanning to the maxima
  // beside it; the best few (by the output error of their start) refined
  // within their span.
  struct Basin {
    std::size_t at;
    double lo, hi, start_loss;
  };
  std::vector<Basin> basins;
  const std::size_t K = profile.loss.size();
  const auto& L = profile.loss;
  for (std::size_t k = 0; k < K; ++k) {
    if (!std::isfinite(L[k]) || starts[k].empty()) continue;
    if ((k > 0 && L[k] > L[k - 1]) || (k + 1 < K && L[k] > L[k + 1])) continue;
    if (k > 0 && L[k] == L[k - 1] && !basins.empty() && basins.back().at + 1 == k) continue;  // a flat floor: once
    std::size_t a = k, b = k;
    while (a > 0 && std::isfinite(L[a - 1]) && L[a - 1] >= L[a]) --a;
    while (b + 1 < K && std::isfinite(L[b + 1]) && L[b + 1] >= L[b]) ++b;
    basins.push_back({k, profile.delay_s[a], profile.delay_s[b], kInf});
  }
  if (basins.empty()) {
    out.reason = "no linear start at any delay (try other orders, or a fixed --delay)";
    return out;
  }
  std::sort(basins.begin(), basins.end(), [&](const Basin& x, const Basin& y) { return L[x.at] < L[y.at]; });
  basins.resize(std::min<std::size_t>(basins.size(), static_cast<std::size_t>(2 * o.basins)));
  // Each basin's start: the filter's denominator, or, when one scores
  // better by output error, one with every pole at a single frequency from
  // a log grid between the slowest pole the stretches resolve and a tenth
  // of the sampling rate (the filter's start can sit in a worse optimum,
  // e.g. a slow pole standing in for drift).
  std::vector<std::vector<double>> grid_dens;
  {
    const double lo_p = std::max(2.0 * slowest, 1e-3), hi_p = 2 * M_PI / (10 * dt);
    for (int k = 0; k < 8 && hi_p > lo_p; ++k) {
      const double p = lo_p * std::pow(hi_p / lo_p, k / 7.0);
      std::vector<std::complex<double>> roots;
      for (int j = 0; j < n; ++j) roots.emplace_back(-p * (1.0 + 0.1 * j), 0.0);
      grid_dens.push_back(FromRoots(roots));
    }
  }
  for (Basin& b : basins) {
    auto score = [&](const std::vector<double>& den) {
      const Projection pr = Project(problem, den, profile.delay_s[b.at]);
      return pr.ok ? pr.sse / static_cast<double>(problem.rows.size()) : kInf;
    };
    b.start_loss = score(FromSearch(starts[b.at].data(), n, o.real_poles));
    for (const auto& den : grid_dens) {
      const double l = score(den);
      if (l < b.start_loss) b.start_loss = l, starts[b.at] = ToSearch(den, o.real_poles, slowest);
    }
  }
  std::sort(basins.begin(), basins.end(), [](const Basin& x, const Basin& y) { return x.start_loss < y.start_loss; });
  Refined best;
  for (std::size_t idx = 0; idx < basins.size() && idx < static_cast<std::size_t>(o.basins); ++idx) {
    const Basin& b = basins[idx];
    if (!std::isfinite(b.start_loss)) continue;
    // Bounded by the searched range only: the linear fit's profile is
    // biased by noise, so the output-error optimum may lie past its basin.
    const double hi = o.delay_s ? *o.delay_s : o.max_delay_s;
    // The joint search only has to reach the basin's optimum's neighbourhood
    // (the best is polished below): at most 15 iterations.
    IdentifyOptions joint = o;
    joint.max_iterations = std::min(o.max_iterations, 15);
    const Refined r = Refine(problem, joint, starts[b.at], profile.delay_s[b.at], 0.0, hi, dt, slowest);
    profile.basins.push_back({r.delay, L[b.at], r.loss});
    if (r.loss < best.loss) best = r;
  }
  // The joint search over denominator and delay can stop with a poor
  // denominator (its steps in the delay cross kinks); the best basin is
  // polished: the denominator refitted with the delay held, then the delay
  // by golden section over +-1 sample, the denominator refitted at each.
  if (!o.delay_s && std::isfinite(best.loss)) {
    IdentifyOptions held = o;
    auto at = [&](double d, const std::vector<double>& theta) {
      held.delay_s = d;
      return Refine(problem, held, theta, d, d, d, dt, slowest);
    };
    Refined polished = at(best.delay, best.theta);
    if (polished.loss < best.loss) best = polished;
    const double phi = (std::sqrt(5.0) - 1) / 2;
    double a = std::max(0.0, best.delay - dt), b = std::min(o.max_delay_s, best.delay + dt);
    double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
    Refined f1 = at(x1, best.theta), f2 = at(x2, best.theta);
    for (int it = 0; it < 6; ++it) {
      if (f1.loss < f2.loss) {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - phi * (b - a);
        f1 = at(x1, f2.theta);
      } else {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + phi * (b - a);
        f2 = at(x2, f1.theta);
      }
    }
    for (const Refined& r : {f1, f2})
      if (r.loss < best.loss) best = r;
    // The basin it came from now ends where the polish did.
    const auto basin = std::min_element(profile.basins.begin(), profile.basins.end(),
                                         [](const DelayBasin& x, const DelayBasin& y) { return x.refined_loss < y.refined_loss; });
    if (basin != profile.basins.end() && best.loss < basin->refined_loss) {
      basin->delay_s = best.delay;
      basin->refined_loss = best.loss;
    }
  }
  std::sort(profile.basins.begin(), profile.basins.end(),
            [](const DelayBasin& a, const DelayBasin& b) { return a.refined_loss < b.refined_loss; });
  // Basins whose refinements ended within a sample of a better one's are
  // that one: reported once.
  std::vector<DelayBasin> distinct;
  for (const DelayBasin& b : profile.basins)
    if (std::none_of(distinct.begin(), distinct.end(), [&](const DelayBasin& k) { return std::abs(k.delay_s - b.delay_s) < dt; }))
      distinct.push_back(b);
  profile.basins = distinct;
  if (!std::isfinite(best.loss)) {
    out.reason = "output-error refinement found no stable model (try other orders, or a fixed --delay)";
    return out;
  }
  // 3. The model, and whether a second basin fits as well.
  const Projection pr = Project(problem, best.den, best.delay, true, true);
  out.tf = TransferFunction{pr.num, best.den, best.delay};
  out.offset = pr.offset;
  out.initial_state = pr.free_response;
  out.prediction = pr.prediction;
  double umean = 0;
  for (std::size_t i : problem.rows) umean += u[i];
  out.input_level = umean / static_cast<double>(problem.rows.size());
  out.output_level = out.offset + out.tf.DcGain() * out.input_level;
  for (const auto& r : Roots(out.tf.den)) out.poles_real.push_back(r.real()), out.poles_imag.push_back(r.imag());
  if (o.real_poles || (n <= 2 && m <= 1)) out.process = ToProcessForm(out.tf);
  out.parameters = n + linear + (o.delay_s ? 0 : 1);
  {
    std::vector<double> yr, pr_rows;
    for (std::size_t i : problem.rows) yr.push_back(y[i]), pr_rows.push_back(out.prediction[i]);
    out.fit_percent = FitPercent(yr, pr_rows);
    out.fitted_samples = problem.rows.size();
  }
  out.criteria = CriteriaFromResiduals(pr.residual, out.parameters);
  if (profile.basins.size() > 1 && std::isfinite(profile.basins[1].refined_loss)) {
    const double n_eff = static_cast<double>(problem.rows.size()) * EffectiveFraction(pr.residual);
    const double l1 = profile.basins[0].refined_loss, l2 = profile.basins[1].refined_loss;
    // Likelihood ratio of the two basins with the residual's effective
    // sample count, against chi-square(1) at 95 % (3.84).
    const double lr = n_eff * std::log(l2 / l1);
    const double grid_step = profile.delay_s.size() > 1 ? profile.delay_s[1] - profile.delay_s[0] : dt;
    if (lr < 3.84 && std::abs(profile.basins[1].delay_s - profile.basins[0].delay_s) > 1.5 * grid_step) {
      profile.ambiguous = true;
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "two delay basins fit alike: %.4g s and %.4g s (loss %.4g vs %.4g); the data do not decide "
                    "between them",
                    profile.basins[0].delay_s, profile.basins[1].delay_s, l1, l2);
      profile.note = buf;
    }
  }
  out.ok = true;
  return out;
}

std::vector<double> Predict(const TransferFunction& tf, double offset, const std::vector<double>& t,
                            const std::vector<double>& u, const std::vector<double>& y,
                            const std::vector<Segment>& segments_in) {
  tf.Validate();
  const std::vector<Segment> segments = segments_in.empty() ? WholeRecord(t.size()) : segments_in;
  std::vector<double> den = tf.den, num = tf.num;
  for (double& c : num) c /= tf.den[0];
  for (double& c : den) c /= tf.den[0];
  const int n = static_cast<int>(den.size()) - 1;
  std::vector<double> out(t.size(), std::numeric_limits<double>::quiet_NaN());
  if (n == 0) {
    for (const Segment& s : segments)
      for (std::size_t i = s.begin; i < s.end; ++i)
        out[i] = offset + num.back() * InterpolateLinear(t, u, t[i] - tf.delay_s);
    return out;
  }
  const int m = static_cast<int>(num.size()) - 1;
  auto forced = [&](const StateResponses& r, std::size_t i) {
    double v = 0;
    for (int k = 0; k <= m; ++k) {
      const double c = num[static_cast<std::size_t>(m - k)];
      if (k < n) {
        v += c * r.state[static_cast<std::size_t>(k)][i];
      } else {
        double w = r.delayed[i];
        for (int j = 0; j < n; ++j) w -= den[static_cast<std::size_t>(n - j)] * r.state[static_cast<std::size_t>(j)][i];
        v += c * w;
      }
    }
    return v;
  };
  if (y.empty()) {
    // Each segment in steady state at its first input: the response to the
    // input less that level, from rest, plus the level's steady output.
    // A segment where the process started: at rest at its first sample,
    // driven from then by the delayed input (which may date from before the
    // start: the record holds it).
    for (const Segment& s : segments) {
      if (s.begin >= s.end) continue;
      const double level = s.process_starts ? 0.0 : u[s.begin];
      std::vector<double> w(u.size(), 0.0);
      for (std::size_t i = s.process_starts ? 0 : s.begin; i < u.size(); ++i) w[i] = u[i] - level;
      const StateResponses r = ComputeStateResponses(den, tf.delay_s, t, w, {s});
      for (std::size_t i = s.begin; i < s.end; ++i) out[i] = offset + tf.DcGain() * level + forced(r, i);
    }
    return out;
  }
  // The initial states fitted to y by least squares, the model fixed.
  const StateResponses r = ComputeStateResponses(den, tf.delay_s, t, u, segments);
  for (const Segment& s : segments) {
    std::vector<std::size_t> rows;
    for (std::size_t i = s.begin; i < s.end; ++i)
      if (std::isfinite(y[i])) rows.push_back(i);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n);
    if (!s.process_starts && rows.size() > static_cast<std::size_t>(2 * n)) {
      Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), n);
      Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
      for (std::size_t k = 0; k < rows.size(); ++k) {
        for (int j = 0; j < n; ++j) a(static_cast<Eigen::Index>(k), j) = r.free[static_cast<std::size_t>(j)][rows[k]];
        b(static_cast<Eigen::Index>(k)) = y[rows[k]] - offset - forced(r, rows[k]);
      }
      const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
      if (sol.allFinite()) x0 = sol;
    }
    for (std::size_t i = s.begin; i < s.end; ++i) {
      double v = offset + forced(r, i);
      for (int j = 0; j < n; ++j) v += x0(j) * r.free[static_cast<std::size_t>(j)][i];
      out[i] = v;
    }
  }
  return out;
}

double ValidateFitPercent(const TransferFunction& tf, double offset, const std::vector<double>& t,
                          const std::vector<double>& u, const std::vector<double>& y,
                          const std::vector<Segment>& segments) {
  return FitPercent(y, Predict(tf, offset, t, u, y, segments));
}

std::vector<OrderRow> OrderTable(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                                 const std::vector<double>& tv, const std::vector<double>& uv,
                                 const std::vector<double>& yv, IdentifyOptions o, const std::vector<Segment>& segments,
                                 const std::vector<Segment>& validation_segments) {
  std::vector<OrderRow> rows;
  for (int p = 1; p <= 3; ++p)
    for (int z = 0; z <= std::min(p, 2); ++z) {  // thesis Table 3: (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2)
      o.poles = p;
      o.zeros = z;
      const IdentifiedModel mdl = IdentifyTransferFunction(t, u, y, o, segments);
      rows.push_back({p, z, mdl.ok ? mdl.fit_percent : NAN,
                      mdl.ok ? ValidateFitPercent(mdl.tf, mdl.offset, tv, uv, yv, validation_segments) : NAN,
                      mdl.ok ? mdl.criteria.aicc : NAN, mdl.ok ? mdl.tf.delay_s : NAN, mdl.ok});
    }
  return rows;
}

}  // namespace bead::model
