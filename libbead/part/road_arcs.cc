#include "libbead/part/road_arcs.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace bead::part {

double Arc::At(double x) const {
  const double B = k * a, u = std::abs(x - x0) / a;
  return u < 1.0 ? h - B + B * std::pow(1.0 - std::pow(u, p), 1.0 / p) : -B;
}

double Arc::Chord() const {
  const double B = k * a, z0 = h - B;
  if (z0 >= 0.0) return 2.0 * a;
  return 2.0 * a * std::pow(std::max(0.0, 1.0 - std::pow(-z0 / B, p)), 1.0 / p);
}

double LayeredAt(std::span<const Arc> arcs, double x) {
  double s = 0.0;
  for (const Arc& a : arcs) s = std::max(s, a.At(x));
  return s;
}

namespace {

double Rss(std::span<const double> x, std::span<const double> d, std::span<const Arc> arcs) {
  double rss = 0.0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double e = LayeredAt(arcs, x[j]) - d[j];
    rss += e * e;
  }
  return rss;
}

// The parameters kept where an arc means something: a positive height and
// a chord of a few points at least.
// The aspect within [0.02, 50] and the exponent within [1.2, 12] (from
// nearly a cone to nearly a box), the same for all: the first's.
void Clamp(std::vector<Arc>& arcs, double min_a, double min_h) {
  const double k = std::clamp(arcs.front().k, 0.02, 50.0), p = std::clamp(arcs.front().p, 1.2, 12.0);
  for (Arc& a : arcs) a.h = std::max(a.h, min_h), a.a = std::max(a.a, min_a), a.k = k, a.p = p;
}

// Parameter i: x0, h, a of each arc in turn, then the shared aspect and
// exponent (held in the first arc; Clamp hands them to the others).
std::size_t Params(const std::vector<Arc>& arcs, bool free_exponent) { return 3 * arcs.size() + 1 + free_exponent; }
double& Param(std::vector<Arc>& arcs, std::size_t i) {
  if (i == 3 * arcs.size()) return arcs.front().k;
  if (i == 3 * arcs.size() + 1) return arcs.front().p;
  Arc& a = arcs[i / 3];
  return i % 3 == 0 ? a.x0 : (i % 3 == 1 ? a.h : a.a);
}

// The shared parameters handed from the first arc to the others.
void Share(std::vector<Arc>& arcs) {
  for (Arc& a : arcs) a.k = arcs.front().k, a.p = arcs.front().p;
}

// Forward differences of the residuals (the max of arcs has kinks where
// two meet: a difference across one is still the slope of one side).
Eigen::MatrixXd Jacobian(std::span<const double> x, const std::vector<Arc>& arcs, const Eigen::VectorXd& base,
                         std::size_t params) {
  Eigen::MatrixXd J(x.size(), params);
  std::vector<Arc> moved = arcs;
  for (std::size_t i = 0; i < params; ++i) {
    double& p = Param(moved, i);
    const double keep = p, step = 1e-4 * std::max(1.0, std::abs(keep));
    p = keep + step;
    Share(moved);
    for (std::size_t j = 0; j < x.size(); ++j) J(j, i) = (LayeredAt(moved, x[j]) - base[j]) / step;
    p = keep;
    Share(moved);
  }
  return J;
}

}  // namespace

ArcFit FitArcs(std::span<const double> x, std::span<const double> d, std::vector<Arc> start, double min_a, double min_h,
               bool free_exponent) {
  ArcFit fit;
  fit.arcs = std::move(start);
  if (fit.arcs.empty()) return fit;
  Clamp(fit.arcs, min_a, min_h);
  const std::size_t params = Params(fit.arcs, free_exponent);
  if (x.size() < params + 1) return fit;
  fit.rss = Rss(x, d, fit.arcs);
  double lambda = 1e-3;
  bool converged = false;
  for (int it = 0; it < 60 && !converged; ++it) {
    Eigen::VectorXd surface(x.size()), r(x.size());
    for (std::size_t j = 0; j < x.size(); ++j) surface[j] = LayeredAt(fit.arcs, x[j]), r[j] = surface[j] - d[j];
    const Eigen::MatrixXd J = Jacobian(x, fit.arcs, surface, params);
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool better = false;
    for (int tries = 0; tries < 8 && !better; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * (JtJ.diagonal().array() + 1e-12).matrix();
      const Eigen::VectorXd step = A.ldlt().solve(-g);
      std::vector<Arc> trial = fit.arcs;
      for (std::size_t i = 0; i < params; ++i) Param(trial, i) += step[i];
      Clamp(trial, min_a, min_h);
      const double rss = Rss(x, d, trial);
      if (std::isfinite(rss) && rss < fit.rss) {
        const double gain = fit.rss - rss;
        fit.arcs = std::move(trial);
        fit.rss = rss;
        lambda = std::max(lambda * 0.3, 1e-9);
        better = true;
        converged = gain < 1e-10 * fit.rss;
      } else {
        lambda *= 10.0;
      }
    }
    if (!better) break;
  }
  fit.ok = std::isfinite(fit.rss);
  return fit;
}

}  // namespace bead::part
