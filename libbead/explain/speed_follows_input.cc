#include "libbead/explain/speed_follows_input.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace bead::explain {
namespace {

constexpr double kWindowS = 0.05;  // the speed's differencing span

// The wheel's angular speed at each sample (NaN where it cannot be told).
std::vector<double> WheelSpeed(const SeriesData& d, const std::vector<double>& angle) {
  const std::size_t n = d.size();
  std::vector<double> speed(n, NAN);
  if (n < 3) return speed;
  const double span = d.t.back() - d.t.front();
  const auto half = static_cast<std::size_t>(
      std::max(1.0, std::round(0.5 * kWindowS / std::max(span / static_cast<double>(n - 1), 1e-9))));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i >= half ? i - half : 0, b = std::min(n - 1, i + half);
    const double dt = d.t[b] - d.t[a];
    if (dt > 0 && std::isfinite(angle[a]) && std::isfinite(angle[b])) speed[i] = (angle[b] - angle[a]) / dt;
  }
  return speed;
}

// The wheel's angular speed and its rate of change at each sample: a
// quadratic in time fitted to the angle over kSlopeWindowS about it (NaN
// where fewer than five samples lie within it, or an angle there is not
// known). Over 0.2 s an encoder's quantisation barely moves the rate of
// change (a steady wheel's correlation below: 0.9993 at 10000 counts per
// revolution, 0.945 over 0.1 s), and a stepped wheel's steps still show.
// Fitted in time, not by series/savgol.h: the samples are at extrusion
// times, spaced as unevenly as the wheel's speed changes.
constexpr double kSlopeWindowS = 0.2;
void SpeedAndAcceleration(const SeriesData& d, const std::vector<double>& angle, std::vector<double>& speed,
                          std::vector<double>& accel) {
  const std::size_t n = d.size();
  speed.assign(n, NAN), accel.assign(n, NAN);
  std::size_t a = 0, b = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (d.t[i] - d.t[a] > 0.5 * kSlopeWindowS) ++a;
    while (b + 1 < n && d.t[b + 1] - d.t[i] <= 0.5 * kSlopeWindowS) ++b;
    if (b - a + 1 < 5) continue;
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    bool ok = true;
    for (std::size_t j = a; j <= b; ++j) {
      const double x = d.t[j] - d.t[i];
      const Eigen::Vector3d row(1.0, x, x * x);
      ok = ok && std::isfinite(angle[j]);
      m += row * row.transpose(), r += row * (angle[j] - angle[i]);
    }
    if (!ok) continue;
    const Eigen::Vector3d c = m.ldlt().solve(r);
    speed[i] = c(1), accel[i] = 2.0 * c(2);
  }
}

const RotatingPart* Wheel(const SeriesData& d) {
  for (const RotatingPart& p : d.parts)
    if (p.name == "wheel" && p.angle_rad.size() == d.size()) return &p;
  return nullptr;
}

}  // namespace

double OffsetDelayCorrelationFromSpeed(const SeriesData& d) {
  const RotatingPart* wheel = Wheel(d);
  const std::size_t n = d.size();
  if (!wheel || n < 10) return NAN;
  std::vector<double> w, dw;
  SpeedAndAcceleration(d, wheel->angle_rad, w, dw);
  std::vector<std::size_t> rows;
  for (std::size_t i = 1; i + 1 < n; ++i)
    if (std::isfinite(w[i]) && std::isfinite(dw[i]) && std::abs(w[i]) > 0 && d.t[i + 1] > d.t[i - 1]) rows.push_back(i);
  if (rows.size() < 10) return NAN;
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd nuisance(m, 2);
  Eigen::VectorXd by_delay(m), by_offset(m);
  for (Eigen::Index r = 0; r < m; ++r) {
    const std::size_t i = rows[static_cast<std::size_t>(r)];
    const double slope = (d.base[i + 1] - d.base[i - 1]) / (d.t[i + 1] - d.t[i - 1]);
    nuisance(r, 0) = 1.0, nuisance(r, 1) = d.base[i];
    by_delay(r) = slope;
    by_offset(r) = (slope - d.base[i] * dw[i] / w[i]) / w[i];
  }
  // What the gain and operating point leave of each.
  const auto qr = nuisance.colPivHouseholderQr();
  const Eigen::VectorXd a = by_delay - nuisance * qr.solve(by_delay);
  const Eigen::VectorXd b = by_offset - nuisance * qr.solve(by_offset);
  const double den = a.norm() * b.norm();
  return den > 0 ? a.dot(b) / den : NAN;
}

double SpeedShareFromInput(const SeriesData& d) {
  const RotatingPart* wheel = Wheel(d);
  if (!wheel) return NAN;
  const std::vector<double> speed = WheelSpeed(d, wheel->angle_rad);
  std::vector<const std::vector<double>*> columns;
  for (const auto& c : d.dynamics) columns.push_back(&c);
  if (columns.empty()) columns.push_back(&d.u);
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < d.size(); ++i) {
    bool ok = std::isfinite(speed[i]);
    for (const auto* c : columns) ok = ok && std::isfinite((*c)[i]);
    if (ok) rows.push_back(i);
  }
  if (rows.size() < columns.size() + 10) return NAN;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(columns.size() + 1));
  Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto row = static_cast<Eigen::Index>(r);
    b(row) = speed[rows[r]];
    a(row, 0) = 1.0;
    for (std::size_t c = 0; c < columns.size(); ++c) a(row, static_cast<Eigen::Index>(c + 1)) = (*columns[c])[rows[r]];
  }
  const double mean = b.mean();
  const double total = (b.array() - mean).square().sum();
  if (!(total > 1e-18 * b.squaredNorm())) return NAN;  // a steady wheel: nothing to share
  for (Eigen::Index c = 0; c < a.cols(); ++c)
    if (const double norm = a.col(c).norm(); norm > 0) a.col(c) /= norm;
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  const double left = (b - a * x).squaredNorm();
  return std::clamp(1.0 - left / total, 0.0, 1.0);
}

}  // namespace bead::explain
