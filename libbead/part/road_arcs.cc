#include "libbead/part/road_arcs.h"

#include <algorithm>
#include <cmath>

#include "libbead/part/least_squares.h"

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

// The parameters: x0, h, a of each arc in turn, then the shared aspect
// and, when free, the shared exponent.
Eigen::VectorXd ToVector(const std::vector<Arc>& arcs, bool free_exponent) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(3 * arcs.size() + 1 + free_exponent));
  for (std::size_t i = 0; i < arcs.size(); ++i)
    v.segment(static_cast<Eigen::Index>(3 * i), 3) << arcs[i].x0, arcs[i].h, arcs[i].a;
  v[static_cast<Eigen::Index>(3 * arcs.size())] = arcs.front().k;
  if (free_exponent) v[static_cast<Eigen::Index>(3 * arcs.size() + 1)] = arcs.front().p;
  return v;
}

// The arcs at v, kept where an arc means something: a positive height, a
// half-width of a few points at least, the aspect within [0.02, 50] and
// the exponent within [1.2, 12] (from nearly a cone to nearly a box), the
// same for all.
void FromVector(const Eigen::VectorXd& v, double min_a, double min_h, std::vector<Arc>& arcs) {
  const std::size_t n = arcs.size();
  const double k = std::clamp(v[static_cast<Eigen::Index>(3 * n)], 0.02, 50.0);
  const double p = static_cast<std::size_t>(v.size()) > 3 * n + 1
                       ? std::clamp(v[static_cast<Eigen::Index>(3 * n + 1)], 1.2, 12.0)
                       : std::clamp(arcs.front().p, 1.2, 12.0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto at = static_cast<Eigen::Index>(3 * i);
    arcs[i] = Arc{v[at], std::max(v[at + 1], min_h), std::max(v[at + 2], min_a), k, p};
  }
}

}  // namespace

ArcFit FitArcs(std::span<const double> x, std::span<const double> d, std::vector<Arc> start, double min_a, double min_h,
               bool free_exponent) {
  ArcFit fit;
  fit.arcs = std::move(start);
  if (fit.arcs.empty() || x.size() < 3 * fit.arcs.size() + 3) return fit;
  std::vector<Arc> scratch = fit.arcs;
  LeastSquares problem;
  problem.residuals = [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
    FromVector(v, min_a, min_h, scratch);
    r.resize(static_cast<Eigen::Index>(x.size()));
    for (std::size_t j = 0; j < x.size(); ++j) r[static_cast<Eigen::Index>(j)] = LayeredAt(scratch, x[j]) - d[j];
  };
  problem.keep = [&](Eigen::VectorXd& v) {
    FromVector(v, min_a, min_h, scratch);
    v = ToVector(scratch, free_exponent);
  };
  const LeastSquaresFit result = Minimise(problem, ToVector(fit.arcs, free_exponent), 60);
  FromVector(result.p, min_a, min_h, fit.arcs);
  fit.rss = result.rss;
  fit.ok = std::isfinite(fit.rss);
  return fit;
}

}  // namespace bead::part
