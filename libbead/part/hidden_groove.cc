#include "libbead/part/hidden_groove.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace bead::part {
namespace {

// The ellipse: centre (x0, z0), semi-axes a across, b up.
struct Ellipse {
  double x0 = 0.0, z0 = 0.0, a = 1.0, b = 1.0;
  // Half its height at x (0 off it).
  double Half(double x) const {
    const double u = (x - x0) / a;
    return std::abs(u) < 1.0 ? b * std::sqrt(1.0 - u * u) : 0.0;
  }
  double& operator[](std::size_t i) { return i == 0 ? x0 : i == 1 ? z0 : i == 2 ? a : b; }
};

// The points around the bead with the surface below under each.
struct Window {
  std::vector<double> x, z, old;
};

double Seen(const Ellipse& e, double x, double old) {
  const double h = e.Half(x);
  return h > 0.0 ? std::max(old, e.z0 + h) : old;
}

double Rss(const Window& w, const Ellipse& e) {
  double rss = 0.0;
  for (std::size_t j = 0; j < w.x.size(); ++j) {
    const double r = Seen(e, w.x[j], w.old[j]) - w.z[j];
    rss += r * r;
  }
  return rss;
}

// The groove: the ellipse's lower outline above the surface below.
double Groove(const Ellipse& e, const SurfaceGrid& below, double shift) {
  const double step = std::max(below.dx_mm, e.a / 400.0);
  double sum = 0.0;
  for (double x = e.x0 - e.a + 0.5 * step; x < e.x0 + e.a; x += step) {
    const double old = below.At(x - shift);
    if (std::isfinite(old)) sum += std::max(0.0, e.z0 - e.Half(x) - old) * step;
  }
  return sum;
}

void Keep(Ellipse& e, double min_a) { e.a = std::max(e.a, min_a), e.b = std::max(e.b, 1e-3); }

// Levenberg-Marquardt from `e`; the Jacobian at the end in J.
double Fit(const Window& w, Ellipse& e, double min_a, Eigen::MatrixXd& J) {
  double rss = Rss(w, e), lambda = 1e-3;
  auto jacobian = [&](const Ellipse& at) {
    J.resize(static_cast<Eigen::Index>(w.x.size()), 4);
    for (std::size_t i = 0; i < 4; ++i) {
      Ellipse moved = at;
      const double step = 1e-5 * std::max(1.0, std::abs(moved[i]));
      moved[i] += step;
      for (std::size_t j = 0; j < w.x.size(); ++j)
        J(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) =
            (Seen(moved, w.x[j], w.old[j]) - Seen(at, w.x[j], w.old[j])) / step;
    }
  };
  bool converged = false;
  for (int it = 0; it < 80 && !converged; ++it) {
    jacobian(e);
    Eigen::VectorXd r(static_cast<Eigen::Index>(w.x.size()));
    for (std::size_t j = 0; j < w.x.size(); ++j) r[static_cast<Eigen::Index>(j)] = Seen(e, w.x[j], w.old[j]) - w.z[j];
    const Eigen::Matrix4d JtJ = J.transpose() * J;
    const Eigen::Vector4d g = J.transpose() * r;
    bool better = false;
    for (int tries = 0; tries < 8 && !better; ++tries) {
      Eigen::Matrix4d A = JtJ;
      A.diagonal() += lambda * (JtJ.diagonal().array() + 1e-12).matrix();
      const Eigen::Vector4d step = A.ldlt().solve(-g);
      Ellipse trial = e;
      for (std::size_t i = 0; i < 4; ++i) trial[i] += step[static_cast<Eigen::Index>(i)];
      Keep(trial, min_a);
      const double next = Rss(w, trial);
      if (std::isfinite(next) && next < rss) {
        converged = rss - next < 1e-10 * rss;
        e = trial, rss = next, lambda = std::max(lambda * 0.3, 1e-9), better = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!better) break;
  }
  jacobian(e);
  return rss;
}

// The groove's 1-sigma: the fit's covariance (s2 (J^T J)^-1) through the
// groove's gradient; the surface below known to its own noise (its grid's
// variance, one independent value per point spacing) and its place to the
// shift's sigma, both moving the groove as much as the fit's own error
// does. NaN where the fit cannot place the bead's sides (J^T J singular).
double GrooveSigma(const Ellipse& e, const Eigen::MatrixXd& J, double s2, double groove, const SurfaceGrid& below,
                   double shift, double shift_sigma, double spacing) {
  Eigen::FullPivLU<Eigen::Matrix4d> lu(Eigen::Matrix4d(J.transpose() * J));
  if (!lu.isInvertible()) return NAN;
  const Eigen::Matrix4d cov = s2 * lu.inverse();
  Eigen::Vector4d grad;
  for (std::size_t i = 0; i < 4; ++i) {
    Ellipse moved = e;
    const double step = 1e-4 * std::max(1.0, std::abs(moved[i]));
    moved[i] += step;
    grad[static_cast<Eigen::Index>(i)] = (Groove(moved, below, shift) - groove) / step;
  }
  double below_var = 0.0;
  const double step = std::max(below.dx_mm, spacing);
  for (double at = e.x0 - e.a + 0.5 * step; at < e.x0 + e.a; at += step)
    if (e.z0 - e.Half(at) > below.At(at - shift)) below_var += below.VarianceAt(at - shift) * step * step;
  const double ds = std::max(1e-3, shift_sigma);
  const double by_shift = (Groove(e, below, shift + ds) - Groove(e, below, shift - ds)) / (2.0 * ds) * shift_sigma;
  return std::sqrt(std::max(0.0, grad.dot(cov * grad)) + below_var + by_shift * by_shift);
}

}  // namespace

HiddenGroove EstimateHiddenGroove(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below,
                                  double shift, double shift_sigma, double center, double width, double height) {
  HiddenGroove out;
  if (!(width > 0.0) || !(height > 0.0)) return out;
  Window w;
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double old = below.At(x[j] - shift);
    if (std::abs(x[j] - center) < width && std::isfinite(old) && std::isfinite(z[j]))
      w.x.push_back(x[j]), w.z.push_back(z[j]), w.old.push_back(old);
  }
  if (w.x.size() < 12) return out;
  const double spacing = (w.x.back() - w.x.front()) / static_cast<double>(w.x.size() - 1);
  const double base = below.At(center - shift);
  // Started sunk to four depths (its centre on the surface below, a
  // quarter, half and three quarters of its height above) and two widths:
  // the least residual kept.
  Ellipse best;
  Eigen::MatrixXd J, best_J;
  double best_rss = INFINITY;
  for (double lift : {0.0, 0.25, 0.5, 0.75})
    for (double across : {0.5, 0.6}) {
      Ellipse e{center, base + lift * height, across * width, height * (1.0 - lift)};
      const double rss = Fit(w, e, 2.0 * spacing, J);
      if (rss < best_rss) best_rss = rss, best = e, best_J = J;
    }
  out.fit_rms_mm = std::sqrt(best_rss / static_cast<double>(w.x.size()));
  out.hidden_mm2 = Groove(best, below, shift);
  const double dof = static_cast<double>(w.x.size()) - 4.0;
  out.sigma_mm2 = GrooveSigma(best, best_J, best_rss / dof, out.hidden_mm2, below, shift, shift_sigma, spacing);
  out.ok = std::isfinite(out.hidden_mm2) && std::isfinite(out.sigma_mm2);
  return out;
}

}  // namespace bead::part
