#include "libbead/explain/explain_loop.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "libbead/core/error.h"
#include "libbead/fit/solver_options.h"
#include "libbead/model/fit_metrics.h"

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Active {
  Effect effect;
  std::vector<double> params;  // nonlinear..., linear...
  std::size_t nl() const { return effect.nonlinear.size(); }
};
using Set = std::vector<Active>;

std::size_t ParameterCount(const Set& set) {
  std::size_t p = 0;
  for (const Active& a : set) p += a.params.size();
  return p;
}

bool HasNonlinear(const Set& set) {
  for (const Active& a : set)
    if (a.nl() > 0) return true;
  return false;
}

// y and base under the set's shifts.
void Shifted(const SeriesData& d, const Set& set, std::vector<double>& y, std::vector<double>& base) {
  double shift = 0;
  std::vector<double> delay(d.size(), 0.0);
  bool delayed = false;
  for (const Active& a : set) {
    shift += a.effect.PositionShift(a.params.data());
    if (a.effect.IsDelay()) {
      a.effect.AddDelay(d, a.params.data(), delay);
      delayed = true;
    }
  }
  if (shift == 0.0 && !delayed) {
    y = d.y;
    base = d.base;
  } else if (d.shifted) {
    d.shifted(shift, delay, y, base);
  } else {
    y = d.y;
    base = d.base_delayed(delay);
  }
}

// Measured (possibly shifted) y and the set's prediction.
void Evaluate(const SeriesData& d, const Set& set, std::vector<double>& y, std::vector<double>& pred) {
  std::vector<double> base;
  Shifted(d, set, y, base);
  const std::size_t n = d.size();
  std::vector<double> mult(n, 1.0), add(n, 0.0);
  for (const Active& a : set) {
    const auto cols = a.effect.Columns(d, a.params.data());
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const double c = a.params[a.nl() + j];
      auto& target = a.effect.kind == Effect::Kind::kMultiplicative ? mult : add;
      for (std::size_t i = 0; i < n; ++i) target[i] += c * cols[j][i];
    }
  }
  pred.resize(n);
  for (std::size_t i = 0; i < n; ++i) pred[i] = base[i] * mult[i] + add[i];
}

std::vector<double> Residual(const SeriesData& d, const Set& set) {
  std::vector<double> y, pred;
  Evaluate(d, set, y, pred);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] -= pred[i];
  return y;
}

double Sse(const std::vector<double>& r, const std::vector<std::size_t>& rows) {
  double s = 0;
  for (std::size_t i : rows)
    if (std::isfinite(r[i])) s += r[i] * r[i];
  return s;
}

// The linear parameters for the current nonlinear ones, by least squares on
// `rows`; returns the design matrix (its columns: the linear parameters in
// order), which depends on the nonlinear parameters only.
Eigen::MatrixXd SolveLinear(const SeriesData& d, Set& set, const std::vector<std::size_t>& rows) {
  std::vector<double> y, base;
  Shifted(d, set, y, base);
  std::vector<std::vector<double>> columns;
  std::vector<std::pair<std::size_t, std::size_t>> where;  // (effect, linear index)
  for (std::size_t e = 0; e < set.size(); ++e) {
    auto cols = set[e].effect.Columns(d, set[e].params.data());
    for (std::size_t j = 0; j < cols.size(); ++j) {
      if (set[e].effect.kind == Effect::Kind::kMultiplicative)
        for (std::size_t i = 0; i < cols[j].size(); ++i) cols[j][i] *= base[i];
      columns.push_back(std::move(cols[j]));
      where.push_back({e, j});
    }
  }
  if (columns.empty()) return {};
  Eigen::MatrixXd a(rows.size(), columns.size());
  Eigen::VectorXd b(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::size_t i = rows[r];
    b(r) = y[i] - base[i];
    for (std::size_t c = 0; c < columns.size(); ++c) a(r, c) = columns[c][i];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  for (std::size_t c = 0; c < columns.size(); ++c) set[where[c].first].params[set[where[c].first].nl() + where[c].second] = x(c);
  return a;
}

struct CostFunctor {
  const SeriesData& data;
  Set shape;
  const std::vector<std::size_t>& rows;
  bool operator()(double const* const* params, double* residuals) const {
    Set set = shape;
    for (std::size_t e = 0; e < set.size(); ++e)
      for (std::size_t k = 0; k < set[e].params.size(); ++k) set[e].params[k] = params[e][k];
    const std::vector<double> r = Residual(data, set);
    for (std::size_t k = 0; k < rows.size(); ++k) residuals[k] = std::isfinite(r[rows[k]]) ? r[rows[k]] : 0.0;
    return true;
  }
};

struct Uncertainty {
  bool ok = false;
  std::vector<std::vector<double>> sd;  // per effect, per parameter
};

// Joint refinement of every parameter (Ceres, central differences); with
// `uncertainty`, the 95 % half-widths as described in explain_loop.h.
void Refine(const SeriesData& d, Set& set, const std::vector<std::size_t>& rows, Uncertainty* uncertainty) {
  if (set.empty()) return;
  if (HasNonlinear(set)) {
    ceres::Problem problem;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<CostFunctor, ceres::CENTRAL>(new CostFunctor{d, set, rows});
    std::vector<double*> blocks;
    for (Active& a : set) {
      cost->AddParameterBlock(static_cast<int>(a.params.size()));
      blocks.push_back(a.params.data());
    }
    cost->SetNumResiduals(static_cast<int>(rows.size()));
    problem.AddResidualBlock(cost, nullptr, blocks);
    // A nonlinear parameter stays within its search grid (a time constant
    // the data cannot pin would run off to infinity).
    for (std::size_t e = 0; e < set.size(); ++e)
      for (std::size_t k = 0; k < set[e].nl(); ++k) {
        const auto& grid = set[e].effect.grid[k];
        problem.SetParameterLowerBound(blocks[e], static_cast<int>(k), grid.front());
        problem.SetParameterUpperBound(blocks[e], static_cast<int>(k), grid.back());
      }
    ceres::Solver::Summary summary;
    ceres::Solve(fit::QuietDenseOptions(30), &problem, &summary);
    if (!uncertainty) return;
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    std::vector<std::pair<const double*, const double*>> pairs;
    for (double* b : blocks) pairs.push_back({b, b});
    // Standard deviations from the covariance blocks; parameters [0, held)
    // of an effect were held (unbounded), or all of them when it is `fixed`.
    auto collect = [&](ceres::Covariance& cov, bool nonlinear_held, const std::vector<bool>& fixed) {
      uncertainty->sd.clear();
      for (std::size_t e = 0; e < set.size(); ++e) {
        const std::size_t m = set[e].params.size();
        std::vector<double> sd(m, kInf);
        if (!fixed[e]) {
          std::vector<double> c(m * m);  // in the ambient space, also with a manifold
          cov.GetCovarianceBlock(blocks[e], blocks[e], c.data());
          for (std::size_t k = nonlinear_held ? set[e].nl() : 0; k < m; ++k) sd[k] = std::sqrt(std::max(c[k * m + k], 0.0));
        }
        uncertainty->sd.push_back(sd);
      }
      uncertainty->ok = true;
    };
    {
      // A rank-deficient covariance is an expected outcome here (handled
      // below); keep Ceres from logging it as an error.
      const int level = FLAGS_minloglevel;
      FLAGS_minloglevel = google::GLOG_FATAL;
      ceres::Covariance cov(co);
      const bool computed = cov.Compute(pairs, &problem);
      FLAGS_minloglevel = level;
      if (computed) {
        collect(cov, false, std::vector<bool>(set.size(), false));
        return;
      }
    }
    // Some nonlinear parameter is not identified by the data: its interval
    // is unbounded, and the others' are computed with it held.
    std::vector<bool> held(set.size(), false);
    std::vector<std::pair<const double*, const double*>> kept;
    for (std::size_t e = 0; e < set.size(); ++e) {
      const int nl = static_cast<int>(set[e].nl()), m = static_cast<int>(set[e].params.size());
      if (nl == 0) {
        kept.push_back({blocks[e], blocks[e]});
      } else if (nl == m) {
        problem.SetParameterBlockConstant(blocks[e]);
        held[e] = true;
      } else {
        std::vector<int> fixed;
        for (int k = 0; k < nl; ++k) fixed.push_back(k);
        problem.SetManifold(blocks[e], new ceres::SubsetManifold(m, fixed));
        kept.push_back({blocks[e], blocks[e]});
      }
    }
    ceres::Covariance cov(co);
    if (cov.Compute(kept, &problem)) collect(cov, true, held);
    return;
  }
  const Eigen::MatrixXd a = SolveLinear(d, set, rows);
  if (!uncertainty || a.cols() == 0) return;
  // Linear: (A^T A)^-1 directly.
  const Eigen::MatrixXd ata = a.transpose() * a;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(ata);
  if (!lu.isInvertible()) return;
  const Eigen::MatrixXd inv = lu.inverse();
  uncertainty->sd.clear();
  std::size_t c = 0;
  for (const Active& act : set) {
    std::vector<double> sd(act.params.size(), 0.0);
    for (std::size_t k = act.nl(); k < act.params.size(); ++k, ++c) sd[k] = std::sqrt(std::max(inv(c, c), 0.0));
    uncertainty->sd.push_back(sd);
  }
  uncertainty->ok = true;
}

// The newest effect's nonlinear start from its grid (linear ones solved at
// each point), then everything refined together.
void Fit(const SeriesData& d, Set& set, const std::vector<std::size_t>& rows) {
  Active& last = set.back();
  if (last.nl() == 1) {
    double best = kInf, best_value = 0.0;
    for (double v : last.effect.grid[0]) {
      set.back().params[0] = v;
      SolveLinear(d, set, rows);
      const double s = Sse(Residual(d, set), rows);
      if (s < best) best = s, best_value = v;
    }
    set.back().params[0] = best_value;
    SolveLinear(d, set, rows);
  }
  Refine(d, set, rows, nullptr);
}

double Bic(double sse, std::size_t n, std::size_t p) {
  const double nn = static_cast<double>(n);
  return nn * std::log(std::max(sse, 1e-300) / nn) + static_cast<double>(p) * std::log(nn);
}

double LagOneCorrelation(const std::vector<double>& r) {
  double m = 0, c0 = 0, c1 = 0;
  std::size_t n = 0;
  for (double x : r)
    if (std::isfinite(x)) m += x, ++n;
  if (n < 3) return 0.0;
  m /= static_cast<double>(n);
  double prev = std::numeric_limits<double>::quiet_NaN();
  for (double x : r) {
    if (!std::isfinite(x)) continue;
    c0 += (x - m) * (x - m);
    if (std::isfinite(prev)) c1 += (x - m) * (prev - m);
    prev = x;
  }
  return c0 > 0 ? c1 / c0 : 0.0;
}

// Time blocks: every sample's block index, `blocks` of equal duration.
std::vector<std::vector<std::size_t>> Blocks(const std::vector<double>& t, int blocks) {
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(blocks));
  const double t0 = t.front(), span = t.back() - t.front();
  for (std::size_t i = 0; i < t.size(); ++i) {
    auto b = static_cast<std::size_t>(span > 0 ? (t[i] - t0) / span * blocks : 0);
    out[std::min(b, out.size() - 1)].push_back(i);
  }
  return out;
}

// The held-out test: on the held-out samples, the drop in squared error
// per added parameter against the error left per effective sample,
//   F = ((SSE_before - SSE_after) / p) / (SSE_after / N_eff),
// N_eff = N (1 - rho) / (1 + rho) for the lag-one correlation rho of the
// residual left; F p is chi-square with p degrees of freedom when the
// effect is not real (its parameters were fitted on other data, so a false
// effect makes the held-out error larger, not smaller).
double HeldOutF(const SeriesData& v, const Set& before, const Set& after, const std::vector<std::size_t>& rows,
                std::size_t added_parameters) {
  const std::vector<double> rb = Residual(v, before), ra = Residual(v, after);
  const double sse_b = Sse(rb, rows), sse_a = Sse(ra, rows);
  std::vector<double> left;
  for (std::size_t i : rows) left.push_back(ra[i]);
  const double rho = std::clamp(LagOneCorrelation(left), 0.0, 0.99);
  const double n_eff = static_cast<double>(rows.size()) * (1 - rho) / (1 + rho);
  if (!(sse_a > 0) || added_parameters == 0) return 0.0;
  return (sse_b - sse_a) / static_cast<double>(added_parameters) / (sse_a / n_eff);
}

// A periodic term against the residual's own colour: the held-out F of
// the same term on the same part turning at other rates (its angle scaled
// about the start), at least two frequency resolutions away from the
// part's own rate and its second harmonic. A colored residual gives such
// surrogates large F too; a real periodic effect beats all of them.
double LargestSurrogateF(const SeriesData& d, const SeriesData& v, bool separate_validation, const Set& current,
                         const Effect& effect, const std::vector<std::size_t>& estimation,
                         const std::vector<std::size_t>& held_out) {
  const auto& angle = d.parts[static_cast<std::size_t>(effect.part)].angle_rad;
  const double revs = std::abs(angle.back() - angle.front()) / (2 * std::numbers::pi);
  double largest = -kInf;
  for (int k = 2; k <= 6; ++k) {
    for (int sign : {-1, 1}) {
      const double factor = 1.0 + sign * k / revs;
      if (factor < 0.3 || std::abs(factor - 2.0) < 2.0 / revs) continue;
      auto scaled = [&](const SeriesData& src) {
        SeriesData copy = src;
        RotatingPart part = copy.parts[static_cast<std::size_t>(effect.part)];
        const double a0 = part.angle_rad.front();
        for (double& a : part.angle_rad) a = a0 + factor * (a - a0);
        part.name += " (surrogate)";
        copy.parts.push_back(part);
        return copy;
      };
      const SeriesData ds = scaled(d);
      const SeriesData vs = separate_validation ? scaled(v) : ds;
      Effect e = effect;
      e.part = static_cast<int>(ds.parts.size()) - 1;
      Set trial = current;
      trial.push_back(Active{e, std::vector<double>(e.linear.size(), 0.0)});
      Fit(ds, trial, estimation);
      largest = std::max(largest, HeldOutF(vs, current, trial, held_out, trial.back().params.size()));
    }
  }
  return largest;
}

double Rms(const std::vector<double>& r) {
  double s = 0;
  std::size_t n = 0;
  for (double x : r)
    if (std::isfinite(x)) s += x * x, ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : 0.0;
}

double FitOf(const SeriesData& d, const Set& set) {
  std::vector<double> y, pred;
  Evaluate(d, set, y, pred);
  return model::FitPercent(y, pred);
}

// The factor from Ceres's (J^T J)^-1 to parameter standard deviations: the
// residual's standard deviation, times sqrt(N / N_eff) for its lag-one
// correlation (N_eff = N (1 - rho) / (1 + rho)).
double Inflation(const SeriesData& d, const Set& set, const std::vector<std::size_t>& rows) {
  const std::vector<double> r = Residual(d, set);
  const double dof = std::max(1.0, static_cast<double>(rows.size()) - static_cast<double>(ParameterCount(set)));
  const double rho = std::clamp(LagOneCorrelation(r), 0.0, 0.99);
  return std::sqrt(Sse(r, rows) / dof) * std::sqrt((1 + rho) / (1 - rho));
}

Diagnosis Diagnose(const SeriesData& d, const Set& set, const ExplainOptions& o) {
  Diagnosis g;
  g.residual = Residual(d, set);
  g.fit_pct = FitOf(d, set);
  g.rms = Rms(g.residual);
  g.whiteness = ResidualWhiteness(g.residual, o.lags);
  g.input = ResidualInputCorrelation(g.residual, d.u, o.lags);
  g.spectrum = ResidualSpectrum(d.t, g.residual, o.spectrum_max_hz);
  return g;
}

std::vector<FittedParameter> Parameters(const Active& a, const Uncertainty& u, std::size_t index, double inflate) {
  std::vector<FittedParameter> out;
  const std::size_t nl = a.nl();
  for (std::size_t k = 0; k < a.params.size(); ++k) {
    const std::string& name = k < nl ? a.effect.nonlinear[k] : a.effect.linear[k - nl];
    const double sd = u.ok ? u.sd[index][k] * inflate : kInf;
    out.push_back({name, a.params[k], 1.96 * sd});
  }
  if (a.effect.part >= 0 && a.params.size() == 2) {
    // Amplitude and phase of c cos + s sin, with first-order uncertainties.
    const double c = a.params[0], s = a.params[1], amp = std::hypot(c, s);
    const double sd = u.ok ? std::hypot(u.sd[index][0], u.sd[index][1]) / std::sqrt(2.0) * inflate : kInf;
    out.push_back({"amplitude_rel", amp, 1.96 * sd});
    out.push_back({"phase_rad", std::atan2(s, c), amp > 0 ? 1.96 * sd / amp : kInf});
  }
  return out;
}

}  // namespace

ExplainReport Explain(const SeriesData& d, const ExplainOptions& o) {
  if (d.size() < 20 || (o.validation && o.validation->size() < 20))
    throw Error("explain: fewer than 20 samples (" + std::to_string(d.size()) + ") to explain");
  ExplainReport report;
  const std::size_t n = d.size();
  std::vector<std::size_t> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = i;
  const auto blocks = Blocks(d.t, std::max(o.blocks, 4));
  std::vector<std::size_t> estimation, held_out;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    auto& to = b % 2 == 0 ? estimation : held_out;
    to.insert(to.end(), blocks[b].begin(), blocks[b].end());
  }
  const SeriesData& validation = o.validation ? *o.validation : d;
  if (o.validation) {  // another run is held out: estimate on the whole of this one
    estimation = all;
    held_out.resize(validation.size());
    for (std::size_t i = 0; i < held_out.size(); ++i) held_out[i] = i;
  }

  const std::vector<Effect> catalogue = Catalogue(d, o.catalogue);
  Set current;
  report.before = Diagnose(d, current, o);

  std::vector<bool> used(catalogue.size(), false);
  for (int round = 0; round < o.max_effects; ++round) {
    Set current_est = current;
    Refine(d, current_est, estimation, nullptr);
    const double bic_now = Bic(Sse(Residual(d, current_est), estimation), estimation.size(), ParameterCount(current_est));
    int best = -1;
    double best_drop = 0.0, best_t = 0.0;
    const auto candidates_left = static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
    Set best_set;
    for (std::size_t c = 0; c < catalogue.size(); ++c) {
      if (used[c]) continue;
      Set trial = current_est;
      Active a{catalogue[c], std::vector<double>(catalogue[c].nonlinear.size() + catalogue[c].linear.size(), 0.0)};
      trial.push_back(a);
      Fit(d, trial, estimation);
      const double drop = bic_now - Bic(Sse(Residual(d, trial), estimation), estimation.size(), ParameterCount(trial));
      const std::size_t p_new = trial.back().params.size();
      const double t = HeldOutF(validation, current_est, trial, held_out, p_new);
      // Every candidate of the round is a test: Bonferroni keeps the chance
      // of adding a false one in a round at alpha.
      const double level = 1.0 - o.alpha / static_cast<double>(candidates_left);
      bool ok = drop > 0 && t > ChiSquareQuantile(level, static_cast<int>(p_new)) / static_cast<double>(p_new);
      double surrogate = NAN;
      if (ok && catalogue[c].part >= 0) {
        surrogate = LargestSurrogateF(d, validation, o.validation != nullptr, current_est, catalogue[c], estimation, held_out);
        ok = t > surrogate;
      }
      report.candidates.push_back({round, catalogue[c].name, drop, t, surrogate, false});
      if (ok && drop > best_drop) best = static_cast<int>(c), best_drop = drop, best_t = t, best_set = trial;
    }
    if (best < 0) break;
    for (auto& cand : report.candidates)
      if (cand.round == round && cand.name == catalogue[static_cast<std::size_t>(best)].name) cand.accepted = true;
    used[static_cast<std::size_t>(best)] = true;

    // Refit on the whole record, from the estimation-half values.
    Set after = best_set;
    Uncertainty u;
    Refine(d, after, all, &u);
    const std::vector<double> r_before = Residual(d, current), r_after = Residual(d, after);
    const double inflate = Inflation(d, after, all);
    AddedEffect added;
    const Active& a = after.back();
    added.name = a.effect.name;
    added.description = a.effect.description;
    added.tracks = a.effect.tracks;
    added.parameters = Parameters(a, u, after.size() - 1, inflate);
    added.fit_before_pct = FitOf(d, current);
    added.fit_after_pct = FitOf(d, after);
    added.rms_before = Rms(r_before);
    added.rms_after = Rms(r_after);
    added.bic_drop = best_drop;
    added.heldout_f = best_t;
    report.effects_added.push_back(added);
    current = after;
  }
  // Report the kept effects' parameters from the final joint fit.
  if (!current.empty()) {
    Uncertainty u;
    Refine(d, current, all, &u);
    const double inflate = Inflation(d, current, all);
    for (std::size_t e = 0; e < current.size(); ++e)
      report.effects_added[e].parameters = Parameters(current[e], u, e, inflate);
  }

  // The wheel-position shift that best aligns the data, with its interval.
  for (const Effect& e : catalogue) {
    if (e.kind != Effect::Kind::kPositionShift) continue;
    Set trial = current;
    bool present = false;
    for (const Active& a : trial) present |= a.effect.kind == Effect::Kind::kPositionShift;
    if (!present) {
      trial.push_back(Active{e, {0.0}});
      Fit(d, trial, all);
    }
    Uncertainty u;
    Refine(d, trial, all, &u);
    const double inflate = Inflation(d, trial, all);
    for (std::size_t k = 0; k < trial.size(); ++k) {
      if (trial[k].effect.kind != Effect::Kind::kPositionShift) continue;
      report.position_shift_estimated = true;
      report.position_shift_counts = trial[k].params[0];
      report.position_shift_ci95_counts = u.ok ? 1.96 * u.sd[k][0] * inflate : kInf;
    }
  }

  report.after = Diagnose(d, current, o);

  // What is left: every significant peak, matched to a rotating part.
  const double span = d.t.back() - d.t.front();
  for (const SpectrumPeak& peak : report.after.spectrum.peaks) {
    Unexplained u{"periodic", "", peak.frequency_hz, peak.power, peak.false_alarm};
    for (const RotatingPart& part : d.parts) {
      const double rate = std::abs(part.angle_rad.back() - part.angle_rad.front()) / (2 * std::numbers::pi * span);
      for (int k = 1; k <= 3 && u.tracks.empty(); ++k)
        if (std::abs(peak.frequency_hz - k * rate) <= std::max(1.5 / span, 0.03 * peak.frequency_hz))
          u.tracks = part.name + " x" + std::to_string(k);
    }
    if (u.tracks.empty()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "frequency %.3f Hz (no rotating part)", peak.frequency_hz);
      u.tracks = buf;
    }
    report.unexplained.push_back(u);
  }
  if (!report.after.whiteness.white && report.unexplained.empty())
    report.unexplained.push_back({"correlated residual", "no single frequency (not white: chi-square above its 99 % limit)", 0, 0, 1});
  return report;
}

}  // namespace bead::explain
