#include "libbead/model/degenerate_fit.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>

namespace bead::model {
namespace {

std::string Format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[300];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

double MedianStep(const std::vector<double>& t) {
  std::vector<double> dt;
  for (std::size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
  if (dt.empty()) return 0;
  std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

// A pole's time constant: 1 / |Re p| for a real pole, 1 / |p| otherwise.
double TimeConstant(std::complex<double> p) {
  return std::abs(p.imag()) > 1e-9 * std::abs(p) ? 1.0 / std::abs(p) : 1.0 / std::abs(p.real());
}

void FastPoles(const IdentifiedModel& m, double dt, Degeneracy& d) {
  for (const auto& p : PolynomialRoots(m.tf.den)) {
    const double tc = TimeConstant(p);
    if (!(tc < dt)) continue;
    d.findings.push_back(
        Format("a pole at %.4g 1/s: its time constant %.3g s is below the sample interval %.3g s, "
               "so the data cannot see it",
               p.real(), tc, dt));
    d.drop_poles = std::max(d.drop_poles, 1);
    return;
  }
}

void CancellingPairs(const IdentifiedModel& m, Degeneracy& d) {
  const auto poles = PolynomialRoots(m.tf.den);
  for (const auto& z : PolynomialRoots(m.tf.num)) {
    for (const auto& p : poles) {
      if (std::abs(z - p) < 0.05 * std::max(std::abs(p), 1e-12)) {
        d.findings.push_back(Format("a zero at %.4g 1/s all but cancels the pole at %.4g 1/s (%.1f %% apart)", z.real(),
                                    p.real(), 100 * std::abs(z - p) / std::abs(p)));
        d.drop_poles = std::max(d.drop_poles, 1);
        d.drop_zeros = std::max(d.drop_zeros, 1);
        return;
      }
    }
  }
}

// The slope of y on u(t - delay) within the segments, each demeaned, and
// its t statistic: the noise is the model's own residual (y minus its
// prediction, where it has one), its sample count cut by that residual's
// lag-one correlation (AR(1): n (1 - r) / (1 + r)). The slope's own
// residual is no noise estimate: on a step test it is the step response's
// transient, smooth and large, and would hide a gain of the wrong sign.
void GainSign(const IdentifiedModel& m, const std::vector<double>& t, const std::vector<double>& u,
              const std::vector<double>& y, const std::vector<Segment>& segments, Degeneracy& d) {
  std::vector<double> xs, ys, noise;
  const bool predicted = m.prediction.size() == y.size();
  for (const Segment& s : segments) {
    std::vector<double> sx, sy;
    for (std::size_t i = s.begin; i < s.end && i < t.size(); ++i) {
      const double when = t[i] - m.tf.delay_s;
      if (when < t[s.begin]) continue;
      const auto it = std::upper_bound(t.begin(), t.end(), when);
      const std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - t.begin())) - 1;
      sx.push_back(u[k]), sy.push_back(y[i]);
      if (predicted && std::isfinite(m.prediction[i])) noise.push_back(y[i] - m.prediction[i]);
    }
    if (sx.size() < 3) continue;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < sx.size(); ++i) mx += sx[i], my += sy[i];
    mx /= static_cast<double>(sx.size()), my /= static_cast<double>(sy.size());
    for (std::size_t i = 0; i < sx.size(); ++i) xs.push_back(sx[i] - mx), ys.push_back(sy[i] - my);
  }
  const std::size_t n = xs.size();
  if (n < 10) return;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) sxx += xs[i] * xs[i], sxy += xs[i] * ys[i];
  if (!(sxx > 0)) return;
  const double slope = sxy / sxx;
  std::vector<double> r = noise;
  if (r.size() < n / 2) {  // no prediction: the slope's own residual
    r.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) r[i] = ys[i] - slope * xs[i];
  }
  const std::size_t nr = r.size();
  double rr = 0, r1 = 0, rm = 0;
  for (double v : r) rm += v / static_cast<double>(nr);
  for (std::size_t i = 0; i < nr; ++i) rr += (r[i] - rm) * (r[i] - rm);
  for (std::size_t i = 1; i < nr; ++i) r1 += (r[i] - rm) * (r[i - 1] - rm);
  const double rho = std::clamp(rr > 0 ? r1 / rr : 0.0, 0.0, 0.999);
  const double n_eff = std::max(3.0, static_cast<double>(n) * (1 - rho) / (1 + rho));
  const double var = rr / static_cast<double>(nr - 1);
  const double se = std::sqrt(var / sxx * static_cast<double>(n) / n_eff);
  const double gain = m.tf.DcGain();
  if (std::abs(slope) > 4 * se && slope * gain < 0) {
    d.wrong_sign = true;
    d.findings.push_back(
        Format("its steady-state gain %.4g has the opposite sign of the data's slope of output on "
               "the delayed input (%.4g +- %.2g)",
               gain, slope, se));
  }
}

}  // namespace

Degeneracy FindDegeneracy(const IdentifiedModel& m, const std::vector<double>& t, const std::vector<double>& u,
                          const std::vector<double>& y, const std::vector<Segment>& segments) {
  Degeneracy d;
  if (!m.ok || t.size() < 2) return d;
  FastPoles(m, MedianStep(t), d);
  CancellingPairs(m, d);
  GainSign(m, t, u, y, segments.empty() ? std::vector<Segment>{{0, t.size()}} : segments, d);
  return d;
}

bool SmallerStructure(const IdentifyOptions& o, const Degeneracy& d, IdentifyOptions& smaller) {
  if (d.drop_poles == 0 || o.poles - d.drop_poles < 1) return false;
  smaller = o;
  smaller.poles = o.poles - d.drop_poles;
  smaller.zeros = std::max(0, std::min(o.zeros - d.drop_zeros, smaller.poles));
  if (o.real_poles) smaller.zeros = std::min(smaller.zeros, 1);
  return true;
}

std::string UnusableReason(const Degeneracy& d) {
  if (!d.wrong_sign) return "";
  return "the model's gain has the opposite sign of the data's, and a controller or feed-forward built on it would "
         "push the wrong way; try another delay range, structure or order";
}

}  // namespace bead::model
