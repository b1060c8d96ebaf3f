#include "calibration/pin_offset.h"

#include <ceres/ceres.h>

#include "libbead/fit/solver_options.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calibration/student_t.h"
#include "libbead/core/median.h"
#include "libbead/series/encoder.h"

namespace bead::calibration {
namespace {

// Chord of a cylinder crossing the laser plane.
struct ChordResidual {
  ChordResidual(double counts, double width_mm, double mm_per_count) : c(counts), w(width_mm), k(mm_per_count) {}
  template <typename T>
  bool operator()(const T* center, const T* radius, const T* base, T* residual) const {
    const T u = (T(c) - center[0]) * T(k);
    // Floor the radicand so the derivative stays finite at the chord's ends.
    T r2 = radius[0] * radius[0] - u * u;
    if (r2 < T(1e-6)) r2 = T(1e-6);
    residual[0] = T(w) - (T(2.0) * sqrt(r2) + base[0]);
    return true;
  }
  double c, w, k;
};

// Counts travelled since the start read, for each profile: the first step
// is taken modulo the counter forward (the wheel turns toward the laser),
// the rest unwrapped.
std::vector<double> CountsFromStart(const Rig& rig, const PinScan& scan) {
  const ProfileBlock& b = scan.profiles;
  const EncoderTrack track = UnwrapEncoder(b.encoder, rig.encoder, b.t_s);
  double first = rig.encoder.direction * static_cast<double>(b.encoder.empty() ? 0 : b.encoder[0] - scan.start_encoder);
  if (rig.encoder.bits > 0 && rig.encoder.bits < 64) {
    const double modulus = std::ldexp(1.0, rig.encoder.bits);
    first = std::fmod(std::fmod(first, modulus) + modulus, modulus);
  }
  std::vector<double> c(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) c[i] = first + (track.counts[i] - track.counts[0]);
  return c;
}

// Mean spacing of a profile's measured points, mm.
double PointSpacing(const ProfileView& v) {
  double lo = INFINITY, hi = -INFINITY;
  int n = 0;
  for (float x : v.x_mm)
    if (std::isfinite(x)) lo = std::min<double>(lo, x), hi = std::max<double>(hi, x), ++n;
  return n > 1 ? (hi - lo) / (n - 1) : 0.1;
}

}  // namespace

PinScanFit FitPinScan(const Rig& rig, const PinScan& scan, const OffsetOptions& options) {
  PinScanFit fit;
  fit.start_encoder = scan.start_encoder;
  const ProfileBlock& b = scan.profiles;
  fit.profiles = static_cast<int>(b.size());
  if (b.size() < 3) {
    fit.reason = "fewer than 3 profiles";
    return fit;
  }
  const std::vector<double> counts = CountsFromStart(rig, scan);
  ProfileProcessor processor(rig.reference_left, rig.reference_right, options.profile, b.points);
  std::vector<double> c, w;
  double best_width = -1.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const BeadGeometry& g = processor.Process(b.view(i));
    if (!g.valid()) continue;
    c.push_back(counts[i]);
    w.push_back(g.width_mm);
    if (g.width_mm > best_width) best_width = g.width_mm, fit.argmax_counts = counts[i];
  }
  fit.profiles_on_pin = static_cast<int>(c.size());
  if (fit.profiles_on_pin < options.min_profiles_on_pin) {
    fit.reason = "the pin was seen in " + std::to_string(c.size()) + " profiles (need " +
                 std::to_string(options.min_profiles_on_pin) + ")";
    return fit;
  }
  const double k = rig.MmPerCount();
  // Closed-form start: w^2 / 4 = R^2 - (c - c0)^2 k^2 is quadratic in c.
  Eigen::MatrixXd a(c.size(), 3);
  Eigen::VectorXd y(c.size());
  const double c_mid = c[c.size() / 2];
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double d = c[i] - c_mid;
    a.row(static_cast<long>(i)) << 1.0, d, d * d;
    y(static_cast<long>(i)) = w[i] * w[i] / 4.0;
  }
  const Eigen::Vector3d q = a.colPivHouseholderQr().solve(y);
  double center = q(2) < 0 ? c_mid - q(1) / (2 * q(2)) : fit.argmax_counts;
  double radius = q(2) < 0 ? std::sqrt(std::max(q(0) - q(1) * q(1) / (4 * q(2)), 1e-6)) : best_width / 2;
  double base = 0.0;

  ceres::Problem problem;
  // Width resolution: two point spacings (each edge is located within one).
  const double resolution = 2.0 * PointSpacing(b.view(0));
  for (std::size_t i = 0; i < c.size(); ++i)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<ChordResidual, 1, 1, 1, 1>(new ChordResidual(c[i], w[i], k)),
        new ceres::CauchyLoss(std::max(resolution, 1e-3)), &center, &radius, &base);
  problem.SetParameterLowerBound(&radius, 0, 1e-3);
  const ceres::Solver::Options so = fit::QuietDenseOptions(100);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    fit.reason = "the chord fit did not converge: " + summary.message;
    return fit;
  }
  double rss = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    double r = 0.0;
    const double* params[] = {&center, &radius, &base};
    ChordResidual(c[i], w[i], k)(params[0], params[1], params[2], &r);
    rss += r * r;
  }
  const double dof = std::max<double>(1.0, static_cast<double>(c.size()) - 3.0);
  fit.rms_mm = std::sqrt(rss / static_cast<double>(c.size()));
  ceres::Covariance::Options co;
  ceres::Covariance covariance(co);
  std::vector<std::pair<const double*, const double*>> blocks = {{&center, &center}};
  double var = NAN;
  if (covariance.Compute(blocks, &problem)) covariance.GetCovarianceBlock(&center, &center, &var);
  // Ceres assumes unit residual variance: scale by the fit's.
  fit.center_se_counts = std::sqrt(std::max(var, 0.0) * rss / dof);
  fit.center_counts = center;
  fit.radius_mm = radius;
  fit.ok = true;
  return fit;
}

OffsetCalibration CalibrateOffset(const Rig& rig, const PinScanArchive& pins, const OffsetOptions& options) {
  OffsetCalibration cal;
  cal.total = static_cast<int>(pins.scans.size());
  std::vector<double> centers, ses;
  for (const PinScan& scan : pins.scans) {
    cal.scans.push_back(FitPinScan(rig, scan, options));
    if (cal.scans.back().ok) {
      centers.push_back(cal.scans.back().center_counts);
      ses.push_back(cal.scans.back().center_se_counts);
    }
  }
  if (centers.size() < 2) {
    cal.reason = "need at least 2 scans with a fitted pin, have " + std::to_string(centers.size());
    return cal;
  }
  std::vector<double> sorted = centers;
  const double med = MedianInPlace(sorted.data(), sorted.size());
  std::vector<double> dev;
  for (double x : centers) dev.push_back(std::abs(x - med));
  const double robust_sigma =
      std::max(1.4826 * MedianInPlace(dev.data(), dev.size()), 3.0 * MedianInPlace(ses.data(), ses.size()));
  std::vector<double> kept, kept_ses;
  for (PinScanFit& s : cal.scans) {
    if (!s.ok) continue;
    s.outlier = std::abs(s.center_counts - med) > options.outlier_sigmas * robust_sigma;
    if (!s.outlier) {
      kept.push_back(s.center_counts);
      kept_ses.push_back(s.center_se_counts);
    }
  }
  cal.used = static_cast<int>(kept.size());
  if (cal.used < 2) {
    cal.reason = "fewer than 2 scans left after rejecting outliers";
    return cal;
  }
  // Mean and spread about the first kept scan (shifted sums: scans that
  // agree exactly give a spread of exactly 0, not the rounding of a sum).
  const double x0 = kept.front();
  double shift = 0.0;
  for (double x : kept) shift += x - x0;
  shift /= cal.used;
  cal.offset_counts = x0 + shift;
  double ss = 0.0;
  for (double x : kept) ss += (x - x0 - shift) * (x - x0 - shift);
  cal.sd_counts = std::sqrt(ss / (cal.used - 1));
  const double fit_se = MedianInPlace(kept_ses.data(), kept_ses.size());
  double per_scan = cal.sd_counts;
  if (cal.sd_counts < fit_se) {
    per_scan = fit_se;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "the scans agree more closely (sd %.3g counts) than each one's fit allows (standard error %.3g "
                  "counts): are some of them the same scan? The interval uses the fit error.",
                  cal.sd_counts, fit_se);
    cal.note = buf;
  }
  cal.ci95_counts = StudentT975(cal.used - 1) * per_scan / std::sqrt(static_cast<double>(cal.used));
  cal.offset_mm = cal.offset_counts * rig.MmPerCount();
  cal.ci95_mm = cal.ci95_counts * rig.MmPerCount();
  cal.ok = true;
  return cal;
}

}  // namespace bead::calibration
