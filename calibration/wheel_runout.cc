#include "calibration/wheel_runout.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>

#include "libbead/core/error.h"

namespace bead::calibration {
namespace {

constexpr double kDeg = 180.0 / M_PI;

double Wrap360(double deg) {
  deg = std::fmod(deg, 360.0);
  return deg < 0.0 ? deg + 360.0 : deg;
}

}  // namespace

WheelRunout FitWheelRunout(const Rig& rig, const std::vector<double>& t_s, const std::vector<double>& counts,
                           const std::vector<double>& height_mm) {
  std::vector<std::size_t> use;
  for (std::size_t k = 0; k < height_mm.size(); ++k)
    if (std::isfinite(height_mm[k]) && std::isfinite(counts[k]) && std::isfinite(t_s[k])) use.push_back(k);
  WheelRunout r;
  r.profiles_used = static_cast<int>(use.size());
  if (use.size() < 40)
    throw Error("only " + std::to_string(use.size()) +
                " profiles have a reference line: the wheel's runout needs 40 or more, over a whole turn");
  double lo = counts[use.front()], hi = lo;
  for (std::size_t k : use) lo = std::min(lo, counts[k]), hi = std::max(hi, counts[k]);
  r.turns = (hi - lo) / rig.encoder.counts_per_rev;
  if (r.turns < 1.0)
    throw Error("the run covers " + std::to_string(r.turns).substr(0, 4) +
                " of a turn of the wheel: its runout needs at least one whole turn (better several)");
  const double t0 = t_s[use.front()], t1 = t_s[use.back()];
  const double mid = 0.5 * (t0 + t1), half = std::max(0.5 * (t1 - t0), 1e-9);
  const Eigen::Index n = static_cast<Eigen::Index>(use.size());
  Eigen::MatrixXd a(n, 8);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t k = use[static_cast<std::size_t>(i)];
    const double u = (t_s[k] - mid) / half;  // Legendre polynomials on [-1, 1]
    const double theta = 2.0 * M_PI * counts[k] / rig.encoder.counts_per_rev;
    a.row(i) << 1.0, u, 0.5 * (3 * u * u - 1), 0.5 * (5 * u * u * u - 3 * u), std::cos(theta), std::sin(theta),
        std::cos(2 * theta), std::sin(2 * theta);
    y(i) = height_mm[k];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 8)
    throw Error(
        "the wheel's angle and the time do not separate in this run (a wheel turning in step with the "
        "drift?): no runout can be told from it");
  const Eigen::VectorXd p = qr.solve(y);
  const Eigen::VectorXd res = y - a * p;
  const double ss = res.squaredNorm();
  r.residual_rms_mm = std::sqrt(ss / static_cast<double>(n));
  double num = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) num += res(i) * res(i - 1);
  const double rho = std::clamp(ss > 0 ? num / ss : 0.0, 0.0, 0.95);
  r.inflation = (1 + rho) / (1 - rho);
  const Eigen::MatrixXd cov = (a.transpose() * a).inverse() * (ss / static_cast<double>(n - 8)) * r.inflation;

  // Amplitude and phase of c cos + s sin = A cos(theta - phase), with
  // their standard errors to first order.
  auto harmonic = [&](int i, int order, double& amp, double& amp_ci, double& phase_deg, double* phase_ci) {
    const double c = p(i), s = p(i + 1);
    amp = std::hypot(c, s);
    const double vc = cov(i, i), vs = cov(i + 1, i + 1), vcs = cov(i, i + 1);
    const double amp_var = amp > 0 ? (c * c * vc + s * s * vs + 2 * c * s * vcs) / (amp * amp) : vc + vs;
    amp_ci = 1.96 * std::sqrt(std::max(0.0, amp_var));
    phase_deg = Wrap360(std::atan2(s, c) * kDeg / order);
    if (phase_ci) {
      const double ph_var =
          amp > 0 ? (s * s * vc + c * c * vs - 2 * c * s * vcs) / (amp * amp * amp * amp) : M_PI * M_PI;
      *phase_ci = std::min(180.0, 1.96 * std::sqrt(std::max(0.0, ph_var)) * kDeg / order);
    }
  };
  harmonic(4, 1, r.eccentricity_mm, r.eccentricity_ci95_mm, r.phase_deg, &r.phase_ci95_deg);
  harmonic(6, 2, r.twice_mm, r.twice_ci95_mm, r.twice_phase_deg, nullptr);
  // The fitted once + twice curve's peak to peak, and the drift's range.
  double cmin = 1e300, cmax = -1e300;
  for (int j = 0; j < 720; ++j) {
    const double th = 2.0 * M_PI * j / 720;
    const double v = p(4) * std::cos(th) + p(5) * std::sin(th) + p(6) * std::cos(2 * th) + p(7) * std::sin(2 * th);
    cmin = std::min(cmin, v), cmax = std::max(cmax, v);
  }
  r.runout_mm = cmax - cmin;
  double dmin = 1e300, dmax = -1e300;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = a.row(i).head(4).dot(p.head(4));
    dmin = std::min(dmin, d), dmax = std::max(dmax, d);
  }
  r.drift_mm = dmax - dmin;
  return r;
}

}  // namespace bead::calibration
