#include "libbead/model/projection.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "libbead/series/interpolate.h"

namespace bead::model {
namespace {

// Least squares from the normal equations accumulated row by row (no
// design matrix kept), the columns scaled to unit RMS first (the state
// responses differ by orders of magnitude): LDLT, or the pivoted QR of the
// scaled Gram matrix where LDLT finds it singular.
class NormalEquations {
 public:
  explicit NormalEquations(int cols) : ata_(Eigen::MatrixXd::Zero(cols, cols)), atb_(Eigen::VectorXd::Zero(cols)) {}
  void Add(const double* row, double b) {
    const auto p = ata_.rows();
    for (Eigen::Index i = 0; i < p; ++i) {
      atb_(i) += row[i] * b;
      for (Eigen::Index j = 0; j <= i; ++j) ata_(i, j) += row[i] * row[j];
    }
    ++rows_;
  }
  std::optional<Eigen::VectorXd> Solve() const {
    const auto p = ata_.rows();
    Eigen::MatrixXd a = ata_.selfadjointView<Eigen::Lower>();
    Eigen::VectorXd scale(p);
    for (Eigen::Index i = 0; i < p; ++i)
      scale(i) = a(i, i) > 0 && std::isfinite(a(i, i)) ? 1.0 / std::sqrt(a(i, i)) : 1.0;
    a = scale.asDiagonal() * a * scale.asDiagonal();
    const Eigen::VectorXd b = scale.cwiseProduct(atb_);
    Eigen::VectorXd x;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive() &&
        ldlt.vectorD().minCoeff() > 1e-13 * ldlt.vectorD().maxCoeff()) {
      x = ldlt.solve(b);
    } else {
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
      qr.setThreshold(1e-12);
      x = qr.solve(b);
    }
    x = x.cwiseProduct(scale);
    if (!x.allFinite()) return std::nullopt;
    return x;
  }

 private:
  Eigen::MatrixXd ata_;
  Eigen::VectorXd atb_;
  std::size_t rows_ = 0;
};

}  // namespace

Projection Project(const ProjectionProblem& p, const std::vector<double>& den, double delay_s, bool want_residual,
                   bool want_prediction) {
  Projection out;
  const int n = static_cast<int>(den.size()) - 1, m = p.zeros;
  const StateResponses r = ComputeStateResponses(den, delay_s, *p.t, *p.u, p.segments,
                                                 p.initial_state ? std::nullopt : std::optional<double>(0.0));
  // Which segment each row belongs to.
  const std::size_t S = p.segments.size();
  // Each segment's first free-response column, or -1 where the segment
  // starts from rest (the process started there, or --from-rest).
  std::vector<int> free_at(S, -1);
  int free_cols = 0;
  for (std::size_t s = 0; s < S; ++s)
    if (p.initial_state && !p.segments[s].process_starts) free_at[s] = (m + 1) + free_cols, free_cols += n;
  const int cols = (m + 1) + free_cols + (p.offset ? 1 : 0);
  if (p.rows.size() <= static_cast<std::size_t>(cols)) return out;
  auto forced = [&](int k, std::size_t i) {
    if (k < n) return r.state[static_cast<std::size_t>(k)][i];
    double v = r.delayed[i];  // s^n / A(s) = 1 - sum_j a_(n-j) s^j / A(s)
    for (int j = 0; j < n; ++j) v -= den[static_cast<std::size_t>(n - j)] * r.state[static_cast<std::size_t>(j)][i];
    return v;
  };
  // One pass for the normal equations, one for the residual.
  std::vector<double> row(static_cast<std::size_t>(cols));
  auto fill = [&](std::size_t i, std::size_t seg) {
    std::fill(row.begin(), row.end(), 0.0);
    for (int k = 0; k <= m; ++k) row[static_cast<std::size_t>(k)] = forced(m - k, i);  // num in descending powers
    if (free_at[seg] >= 0)
      for (int k = 0; k < n; ++k)
        row[static_cast<std::size_t>(free_at[seg] + k)] = r.free[static_cast<std::size_t>(k)][i];
    if (p.offset) row[static_cast<std::size_t>(cols - 1)] = 1.0;
  };
  NormalEquations ne(cols);
  std::size_t seg = 0;
  for (std::size_t i : p.rows) {
    while (seg + 1 < S && i >= p.segments[seg].end) ++seg;
    fill(i, seg);
    ne.Add(row.data(), (*p.y)[i]);
  }
  const auto solved = ne.Solve();
  if (!solved) return out;
  const Eigen::VectorXd& x = *solved;
  out.num.assign(x.data(), x.data() + m + 1);
  out.offset = p.offset ? x(cols - 1) : 0.0;
  if (p.initial_state)
    for (std::size_t s = 0; s < S; ++s)
      out.free_response.push_back(free_at[s] < 0
                                      ? std::vector<double>(static_cast<std::size_t>(n), 0.0)
                                      : std::vector<double>(x.data() + free_at[s], x.data() + free_at[s] + n));
  auto predict = [&](std::size_t i, std::size_t s) {
    fill(i, s);
    double v = 0;
    for (int c = 0; c < cols; ++c) v += row[static_cast<std::size_t>(c)] * x(c);
    return v;
  };
  out.sse = 0.0;
  if (want_residual) out.residual.resize(p.rows.size());
  seg = 0;
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    const std::size_t i = p.rows[k];
    while (seg + 1 < S && i >= p.segments[seg].end) ++seg;
    const double e = (*p.y)[i] - predict(i, seg);
    out.sse += e * e;
    if (want_residual) out.residual[k] = e;
  }
  if (want_prediction) {
    out.prediction.assign(p.t->size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t s = 0; s < S; ++s)
      for (std::size_t i = p.segments[s].begin; i < p.segments[s].end; ++i) out.prediction[i] = predict(i, s);
  }
  out.ok = std::isfinite(out.sse);
  return out;
}

SvfSignals FilterForSvf(const ProjectionProblem& p, int n, double lambda, double dt) {
  SvfSignals s;
  s.n = n;
  s.m = p.zeros;
  s.lambda = lambda;
  s.half_step = dt / 2;
  // F(s) = lambda^(n+1) / (s + lambda)^(n+1): one order above the model so
  // that even s^n F(s) falls off at high frequency.
  std::vector<double> den = {1.0};
  for (int k = 0; k <= n; ++k) {
    std::vector<double> next(den.size() + 1, 0.0);
    for (std::size_t i = 0; i < den.size(); ++i) next[i] += den[i], next[i + 1] += lambda * den[i];
    den = next;
  }
  const double gain = std::pow(lambda, n + 1);
  // Each signal less its first value, so the filters start in steady state
  // (the constant term takes up the difference).
  std::vector<double> y0 = *p.y, u0 = *p.u;
  for (const Segment& seg : p.segments)
    for (std::size_t i = seg.begin; i < seg.end; ++i) y0[i] = (*p.y)[i] - (*p.y)[seg.begin];
  for (double& v : u0) v -= (*p.u)[0];
  for (double& v : y0)
    if (!std::isfinite(v)) v = 0.0;
  const StateResponses ry = ComputeStateResponses(den, 0.0, *p.t, y0, p.segments);
  const StateResponses ru = ComputeStateResponses(den, 0.0, *p.t, u0, WholeRecord(p.t->size()));
  for (int k = 0; k <= n; ++k) {
    std::vector<double> yk = ry.state[static_cast<std::size_t>(k)], uk = ru.state[static_cast<std::size_t>(k)];
    for (double& v : yk) v *= gain;
    for (double& v : uk) v *= gain;
    s.yf.push_back(std::move(yk));
    s.uf.push_back(std::move(uk));
  }
  return s;
}

std::optional<SvfEstimate> SvfDenominator(const ProjectionProblem& p, const SvfSignals& s, double delay_s) {
  const int n = s.n, m = s.m;
  // Rows past the filters' start-up (and the delay) in each segment.
  const double settle = 6.0 * (n + 1) / s.lambda + delay_s;
  // A constant per segment: each segment's output is taken less its own
  // first value (FilterForSvf), so each has its own constant.
  const int S = static_cast<int>(p.segments.size());
  const int cols = n + m + 1 + S;
  const std::vector<double>& t = *p.t;
  NormalEquations ne(cols);
  std::vector<double> row(static_cast<std::size_t>(cols));
  std::size_t seg = 0, used = 0, j = 0;
  // s^n y = -a1 s^(n-1) y - ... - an y + b0 s^m u + ... + bm u + c;
  // the input read dt / 2 later: held between samples, y lags the
  // continuous output by about half a step, the input is truly held.
  auto fill = [&](std::size_t i, std::size_t segment) {
    for (int k = 0; k < n; ++k) row[static_cast<std::size_t>(k)] = -s.yf[static_cast<std::size_t>(n - 1 - k)][i];
    const double at = t[i] - delay_s - s.half_step;
    while (j + 1 < t.size() && t[j + 1] <= at) ++j;  // rows in time order: the pointer only moves on
    const double f = j + 1 < t.size() && at > t[j] ? (at - t[j]) / (t[j + 1] - t[j]) : 0.0;
    for (int k = 0; k <= m; ++k) {
      const auto& uf = s.uf[static_cast<std::size_t>(m - k)];
      row[static_cast<std::size_t>(n + k)] =
          at <= t[0] ? uf[0] : uf[j] + f * ((j + 1 < t.size() ? uf[j + 1] : uf[j]) - uf[j]);
    }
    for (int k = 0; k < S; ++k)
      row[static_cast<std::size_t>(n + m + 1 + k)] = k == static_cast<int>(segment) ? 1.0 : 0.0;
  };
  std::vector<std::size_t> rows, row_segment;
  for (std::size_t i : p.rows) {
    while (seg + 1 < p.segments.size() && i >= p.segments[seg].end) ++seg;
    if (t[i] - t[p.segments[seg].begin] < settle) continue;
    rows.push_back(i);
    row_segment.push_back(seg);
  }
  if (static_cast<int>(rows.size()) <= 2 * cols) return std::nullopt;
  for (std::size_t q = 0; q < rows.size(); ++q) {
    const std::size_t i = rows[q];
    fill(i, row_segment[q]);
    ne.Add(row.data(), s.yf[static_cast<std::size_t>(n)][i]);
    ++used;
  }
  const auto x = ne.Solve();
  if (!x) return std::nullopt;
  SvfEstimate out;
  out.den = {1.0};
  for (int k = 0; k < n; ++k) out.den.push_back((*x)(k));
  double sse = 0;
  j = 0;
  for (std::size_t q = 0; q < rows.size(); ++q) {
    const std::size_t i = rows[q];
    fill(i, row_segment[q]);
    double e = s.yf[static_cast<std::size_t>(n)][i];
    for (int c = 0; c < cols; ++c) e -= row[static_cast<std::size_t>(c)] * (*x)(c);
    sse += e * e;
  }
  out.equation_loss = sse / static_cast<double>(used);
  return out;
}

}  // namespace bead::model
