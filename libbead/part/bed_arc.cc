#include "libbead/part/bed_arc.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "libbead/core/median.h"

namespace bead::part {
namespace {

struct Points {
  std::vector<double> x, z;
};

// Kasa's algebraic circle: a start for the geometric fit.
bool Algebraic(const Points& p, double& xc, double& zc, double& r) {
  const int n = static_cast<int>(p.x.size());
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    a(i, 0) = p.x[i], a(i, 1) = p.z[i], a(i, 2) = 1.0;
    b(i) = -(p.x[i] * p.x[i] + p.z[i] * p.z[i]);
  }
  const Eigen::Vector3d s = a.colPivHouseholderQr().solve(b);
  xc = -0.5 * s(0), zc = -0.5 * s(1);
  const double r2 = xc * xc + zc * zc - s(2);
  if (!(r2 > 0)) return false;
  r = std::sqrt(r2);
  return true;
}

// Gauss-Newton on |p - c| - R over (xc, zc[, R]).
void Geometric(const Points& p, bool fit_radius, double& xc, double& zc, double& r) {
  const int k = fit_radius ? 3 : 2;
  for (int it = 0; it < 30; ++it) {
    Eigen::MatrixXd j(p.x.size(), k);
    Eigen::VectorXd res(p.x.size());
    for (std::size_t i = 0; i < p.x.size(); ++i) {
      const double dx = p.x[i] - xc, dz = p.z[i] - zc, d = std::hypot(dx, dz);
      res(i) = d - r;
      j(i, 0) = -dx / d, j(i, 1) = -dz / d;
      if (fit_radius) j(i, 2) = -1.0;
    }
    const Eigen::VectorXd step = j.colPivHouseholderQr().solve(-res);
    xc += step(0), zc += step(1);
    if (fit_radius) r += step(2);
    if (step.norm() < 1e-10 * std::max(1.0, r)) break;
  }
}

double Residual(const Points& p, std::size_t i, double xc, double zc, double r) {
  return std::hypot(p.x[i] - xc, p.z[i] - zc) - r;
}

}  // namespace

double BedArc::At(double x) const {
  const double u = x - xc_mm;
  if (!ok || std::abs(u) >= radius_mm) return std::numeric_limits<double>::quiet_NaN();
  return zc_mm + std::sqrt(radius_mm * radius_mm - u * u);
}

BedArc FitBedArc(std::span<const float> x, std::span<const float> z, const ReferenceArea& left,
                 const ReferenceArea& right, double radius) {
  BedArc arc;
  Points p;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(z[i]) && (left.Contains(x[i]) || right.Contains(x[i])))
      p.x.push_back(x[i]), p.z.push_back(z[i]);
  if (p.x.size() < 10) {
    arc.why = "fewer than 10 points of bare bed in the reference areas";
    return arc;
  }
  double xc = 0, zc = 0, r = 0;
  if (!Algebraic(p, xc, zc, r)) {
    arc.why = "the bare bed is not an arc (no circle through its points)";
    return arc;
  }
  // The pipe's top: its centre lies below the surface.
  if (radius > 0) zc += r - radius, r = radius;
  for (int pass = 0; pass < 2; ++pass) {
    Geometric(p, radius <= 0, xc, zc, r);
    if (pass == 1) break;
    std::vector<double> a;
    for (std::size_t i = 0; i < p.x.size(); ++i) a.push_back(std::abs(Residual(p, i, xc, zc, r)));
    std::vector<double> sorted = a;
    const double cut = std::max(3.5 * 1.4826 * MiddleInPlace(sorted), 1e-4);
    Points kept;
    for (std::size_t i = 0; i < p.x.size(); ++i)
      if (a[i] <= cut) kept.x.push_back(p.x[i]), kept.z.push_back(p.z[i]);
    if (kept.x.size() >= 10) p = std::move(kept);
  }
  double ss = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i) ss += std::pow(Residual(p, i, xc, zc, r), 2);
  arc.rms_mm = std::sqrt(ss / static_cast<double>(p.x.size()));
  arc.points = static_cast<int>(p.x.size());
  if (!(r > 0) || !std::isfinite(xc) || !std::isfinite(zc) || zc >= *std::min_element(p.z.begin(), p.z.end())) {
    arc.why = "the fitted arc is not a pipe's top under the bead (centre above the surface or no radius)";
    return arc;
  }
  arc.ok = true, arc.xc_mm = xc, arc.zc_mm = zc, arc.radius_mm = r;
  return arc;
}

}  // namespace bead::part
