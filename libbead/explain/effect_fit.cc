#include "libbead/explain/effect_fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "libbead/fit/solver_options.h"
#include "libbead/series/interpolate.h"

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// y and base under the set's shifts; the base's free responses
// (SeriesData::initial) delayed with it.
void Shifted(const SeriesData& d, const EffectSet& set, std::vector<double>& y, std::vector<double>& base,
             std::vector<std::vector<double>>* initial = nullptr) {
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
  ShiftMemo& memo = d.shift_memo.memo;
  if (memo.valid && memo.shift == shift && memo.delay == delay) {
    y = memo.y;
    base = memo.base;
    if (initial) *initial = memo.initial;
    return;
  }
  std::vector<std::vector<double>> own_initial;
  if (!initial) initial = &own_initial;
  {
    *initial = d.initial;
    if (delayed)
      for (std::size_t c = 0; c < initial->size(); ++c) {
        std::size_t at = 0;  // the delayed times run nearly in order
        for (std::size_t i = 0; i < d.size(); ++i)
          (*initial)[c][i] = InterpolateLinearNear(d.t, d.initial[c], d.t[i] - delay[i], at);
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
  memo.valid = true;
  memo.shift = shift;
  memo.delay = std::move(delay);
  memo.y = y;
  memo.base = base;
  memo.initial = *initial;
}

// Where each effect's nonlinear parameters sit (effect, index).
std::vector<std::pair<std::size_t, std::size_t>> NonlinearSlots(const EffectSet& set, std::size_t first_free) {
  std::vector<std::pair<std::size_t, std::size_t>> slots;
  for (std::size_t e = first_free; e < set.size(); ++e)
    for (std::size_t k = 0; k < set[e].nl(); ++k) slots.push_back({e, k});
  return slots;
}

struct ProjectedCost {
  const SeriesData& data;
  EffectSet shape;
  const std::vector<std::size_t>& rows;
  std::vector<std::pair<std::size_t, std::size_t>> slots;
  bool operator()(double const* const* params, double* residuals) const {
    EffectSet set = shape;
    for (std::size_t s = 0; s < slots.size(); ++s) set[slots[s].first].params[slots[s].second] = params[0][s];
    SolveLinear(data, set, rows);
    const std::vector<double> r = Residual(data, set);
    for (std::size_t k = 0; k < rows.size(); ++k) residuals[k] = std::isfinite(r[rows[k]]) ? r[rows[k]] : 0.0;
    return true;
  }
};

}  // namespace

Active Activate(const Effect& e) { return Active{e, std::vector<double>(e.nonlinear.size() + e.linear.size(), 0.0)}; }

std::size_t ParameterCount(const EffectSet& set) {
  std::size_t p = 0;
  for (const Active& a : set) p += a.params.size();
  return p;
}

void Evaluate(const SeriesData& d, const EffectSet& set, std::vector<double>& y, std::vector<double>& pred) {
  std::vector<double> base;
  std::vector<std::vector<double>> initial;
  Shifted(d, set, y, base, &initial);
  const std::size_t n = d.size();
  std::vector<double> mult(n, 1.0), add(n, 0.0);
  for (const Active& a : set) {
    const auto cols = a.effect.feature == "initial" ? initial : a.effect.Columns(d, a.params.data());
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const double c = a.params[a.nl() + j];
      auto& target = a.effect.kind == Effect::Kind::kMultiplicative ? mult : add;
      for (std::size_t i = 0; i < n; ++i) target[i] += c * cols[j][i];
    }
  }
  pred.resize(n);
  for (std::size_t i = 0; i < n; ++i) pred[i] = base[i] * mult[i] + add[i];
}

std::vector<double> Residual(const SeriesData& d, const EffectSet& set) {
  std::vector<double> y, pred;
  Evaluate(d, set, y, pred);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] -= pred[i];
  return y;
}

double Sse(const std::vector<double>& r, const std::vector<std::size_t>& rows) {
  double s = 0;
  std::size_t finite = 0;
  for (std::size_t i : rows)
    if (std::isfinite(r[i])) s += r[i] * r[i], ++finite;
  // Scaled to all the rows: a shift that pushes samples out of the record
  // (no extrusion time) must not look better for having fewer of them.
  return finite ? s * static_cast<double>(rows.size()) / static_cast<double>(finite) : 0.0;
}

void SolveLinear(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows) {
  std::vector<double> y, base;
  std::vector<std::vector<double>> initial;
  Shifted(d, set, y, base, &initial);
  std::vector<std::vector<double>> columns;
  std::vector<std::pair<std::size_t, std::size_t>> where;  // (effect, linear index)
  for (std::size_t e = 0; e < set.size(); ++e) {
    auto cols = set[e].effect.feature == "initial" ? initial : set[e].effect.Columns(d, set[e].params.data());
    for (std::size_t j = 0; j < cols.size(); ++j) {
      if (set[e].effect.kind == Effect::Kind::kMultiplicative)
        for (std::size_t i = 0; i < cols[j].size(); ++i) cols[j][i] *= base[i];
      columns.push_back(std::move(cols[j]));
      where.push_back({e, j});
    }
  }
  if (columns.empty()) return;
  std::vector<std::size_t> ok;
  for (std::size_t i : rows)
    if (std::isfinite(y[i]) && std::isfinite(base[i])) ok.push_back(i);
  Eigen::MatrixXd a(ok.size(), columns.size());
  Eigen::VectorXd b(ok.size());
  for (std::size_t r = 0; r < ok.size(); ++r) {
    b(static_cast<Eigen::Index>(r)) = y[ok[r]] - base[ok[r]];
    for (std::size_t c = 0; c < columns.size(); ++c)
      a(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = columns[c][ok[r]];
  }
  Eigen::VectorXd scale(a.cols());
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    const double norm = a.col(c).norm();
    scale(c) = norm > 0 ? 1.0 / norm : 1.0;
    a.col(c) *= scale(c);
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b).cwiseProduct(scale);
  for (std::size_t c = 0; c < columns.size(); ++c)
    set[where[c].first].params[set[where[c].first].nl() + where[c].second] =
        std::isfinite(x(static_cast<Eigen::Index>(c))) ? x(static_cast<Eigen::Index>(c)) : 0.0;
}

void SolveLinearOf(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows,
                   const std::string& feature) {
  for (std::size_t e = 0; e < set.size(); ++e) {
    if (set[e].effect.feature != feature || set[e].effect.kind != Effect::Kind::kAdditive) continue;
    for (std::size_t k = set[e].nl(); k < set[e].params.size(); ++k) set[e].params[k] = 0.0;
    const std::vector<double> r = Residual(d, set);  // without the effect
    std::vector<double> y, base;
    std::vector<std::vector<double>> initial;
    Shifted(d, set, y, base, &initial);
    const auto cols = feature == "initial" ? initial : set[e].effect.Columns(d, set[e].params.data());
    std::vector<std::size_t> ok;
    for (std::size_t i : rows)
      if (std::isfinite(r[i])) ok.push_back(i);
    if (cols.empty() || ok.empty()) continue;
    Eigen::MatrixXd a(ok.size(), cols.size());
    Eigen::VectorXd b(ok.size());
    for (std::size_t q = 0; q < ok.size(); ++q) {
      b(static_cast<Eigen::Index>(q)) = r[ok[q]];
      for (std::size_t c = 0; c < cols.size(); ++c)
        a(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(c)) = cols[c][ok[q]];
    }
    const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
    for (std::size_t c = 0; c < cols.size(); ++c)
      set[e].params[set[e].nl() + c] =
          std::isfinite(x(static_cast<Eigen::Index>(c))) ? x(static_cast<Eigen::Index>(c)) : 0.0;
  }
}

void Refine(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows, int max_iterations,
            std::size_t first_free) {
  if (set.empty()) return;
  const auto slots = NonlinearSlots(set, first_free);
  if (slots.empty()) {
    SolveLinear(d, set, rows);
    return;
  }
  std::vector<double> x;
  for (const auto& [e, k] : slots) x.push_back(set[e].params[k]);
  auto* cost =
      new ceres::DynamicNumericDiffCostFunction<ProjectedCost, ceres::CENTRAL>(new ProjectedCost{d, set, rows, slots});
  cost->AddParameterBlock(static_cast<int>(x.size()));
  cost->SetNumResiduals(static_cast<int>(rows.size()));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  // A nonlinear parameter stays within its search grid (a time constant
  // the data cannot pin would run off to infinity).
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const auto& grid = set[slots[s].first].effect.grid[slots[s].second];
    problem.SetParameterLowerBound(x.data(), static_cast<int>(s), grid.front());
    problem.SetParameterUpperBound(x.data(), static_cast<int>(s), grid.back());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(fit::QuietDenseOptions(max_iterations), &problem, &summary);
  for (std::size_t s = 0; s < slots.size(); ++s) set[slots[s].first].params[slots[s].second] = x[s];
  SolveLinear(d, set, rows);
}

void Fit(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows, std::size_t first_free) {
  Active& last = set.back();
  // The first nonlinear parameter from its grid, any others held at their
  // start (0, inside their range).
  if (last.nl() >= 1) {
    double best = kInf, best_value = 0.0;
    for (double v : last.effect.grid[0]) {
      set.back().params[0] = v;
      SolveLinear(d, set, rows);
      const double s = Sse(Residual(d, set), rows);
      if (s < best) best = s, best_value = v;
    }
    set.back().params[0] = best_value;
  }
  Refine(d, set, rows, 30, first_free);
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

}  // namespace bead::explain
