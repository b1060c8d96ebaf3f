#include "libbead/explain/parameter_covariance.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Central differences of the residual in every parameter (linear ones not
// re-solved: the Jacobian of the whole set), rows in the order given.
Eigen::MatrixXd Jacobian(const SeriesData& d, const EffectSet& set, const std::vector<std::size_t>& rows,
                         const std::vector<std::pair<std::size_t, std::size_t>>& slots) {
  Eigen::MatrixXd J(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(slots.size()));
  for (std::size_t c = 0; c < slots.size(); ++c) {
    const auto [e, k] = slots[c];
    EffectSet plus = set, minus = set;
    const double v = set[e].params[k];
    double h = 1e-5 * std::max(std::abs(v), 1e-3);
    if (k < set[e].nl()) {
      const auto& grid = set[e].effect.grid[k];
      h = 1e-3 * (grid.back() - grid.front());
    }
    plus[e].params[k] = v + h;
    minus[e].params[k] = v - h;
    const std::vector<double> rp = Residual(d, plus), rm = Residual(d, minus);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double a = rp[rows[r]], b = rm[rows[r]];
      J(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          std::isfinite(a) && std::isfinite(b) ? (a - b) / (2 * h) : 0.0;
    }
  }
  return J;
}

}  // namespace

std::vector<double> ParameterCovariance::Matrix() const {
  const std::size_t slots = index.size();
  std::vector<double> m(slots * slots, NAN);
  for (std::size_t i = 0; i < slots; ++i)
    for (std::size_t j = 0; j < slots; ++j)
      m[i * slots + j] =
          correlation[i * slots + j] * sd[index[i].first][index[i].second] * sd[index[j].first][index[j].second];
  return m;
}

double ParameterCovariance::Correlation(std::size_t ea, std::size_t pa, std::size_t eb, std::size_t pb) const {
  std::size_t ia = index.size(), ib = index.size();
  for (std::size_t s = 0; s < index.size(); ++s) {
    if (index[s] == std::make_pair(ea, pa)) ia = s;
    if (index[s] == std::make_pair(eb, pb)) ib = s;
  }
  if (ia == index.size() || ib == index.size()) return NAN;
  return correlation[ia * index.size() + ib];
}

ParameterCovariance Covariance(const SeriesData& d, const EffectSet& set, const std::vector<std::size_t>& rows) {
  ParameterCovariance out;
  for (std::size_t e = 0; e < set.size(); ++e)
    for (std::size_t k = 0; k < set[e].params.size(); ++k) out.index.push_back({e, k});
  for (const Active& a : set)
    out.sd.emplace_back(a.params.size(), kInf), out.variance_along.emplace_back(a.params.size(), NAN);
  const std::size_t P = out.index.size();
  out.correlation.assign(P * P, NAN);
  if (P == 0 || rows.size() <= P) return out;
  const std::vector<double> r = Residual(d, set);
  std::vector<double> e;
  for (std::size_t i : rows) e.push_back(r[i]);
  const Eigen::MatrixXd J = Jacobian(d, set, rows, out.index);
  Eigen::MatrixXd H = J.transpose() * J;
  Eigen::VectorXd scale(static_cast<Eigen::Index>(P));
  for (Eigen::Index i = 0; i < H.rows(); ++i) scale(i) = H(i, i) > 0 ? 1.0 / std::sqrt(H(i, i)) : 0.0;
  H = scale.asDiagonal() * H * scale.asDiagonal();
  // The residual's noise model and J' Sigma J under it, with the degrees
  // of freedom the fit used given back (n / (n - P)).
  out.noise = FitArNoise(e);
  const Eigen::MatrixXd js = J * scale.asDiagonal();
  const Eigen::MatrixXd M = js.transpose() * ApplyCovariance(out.noise, js) *
                            (static_cast<double>(rows.size()) / static_cast<double>(rows.size() - P));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const Eigen::MatrixXd V = eig.eigenvectors();
  const double tol = 1e-10 * std::max(lambda.maxCoeff(), 1e-300);
  // The pseudo-inverse on what the data pins; a parameter with weight in
  // the null space is not determined (infinite).
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(lambda.size());
  for (Eigen::Index j = 0; j < lambda.size(); ++j) inv(j) = lambda(j) > tol ? 1.0 / lambda(j) : 0.0;
  const Eigen::MatrixXd Hinv = V * inv.asDiagonal() * V.transpose();
  const Eigen::MatrixXd C = Hinv * M * Hinv;  // in the scaled parameters
  std::vector<bool> pinned(P);
  for (std::size_t c = 0; c < P; ++c) {
    double null_weight = 0;
    for (Eigen::Index j = 0; j < lambda.size(); ++j)
      if (!(lambda(j) > tol)) null_weight += V(static_cast<Eigen::Index>(c), j) * V(static_cast<Eigen::Index>(c), j);
    const auto ci = static_cast<Eigen::Index>(c);
    pinned[c] = null_weight <= 0.01 && scale(ci) != 0.0 && C(ci, ci) > 0;
    out.sd[out.index[c].first][out.index[c].second] = pinned[c] ? std::sqrt(C(ci, ci)) * scale(ci) : kInf;
    if (pinned[c] && Hinv(ci, ci) > 0)
      out.variance_along[out.index[c].first][out.index[c].second] = C(ci, ci) / Hinv(ci, ci);
  }
  for (std::size_t a = 0; a < P; ++a)
    for (std::size_t b = 0; b < P; ++b)
      if (pinned[a] && pinned[b]) {
        const auto ia = static_cast<Eigen::Index>(a), ib = static_cast<Eigen::Index>(b);
        out.correlation[a * P + b] = C(ia, ib) / std::sqrt(C(ia, ia) * C(ib, ib));
      }
  return out;
}

}  // namespace bead::explain
