#include "libbead/explain/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "libbead/series/fourier_sums.h"

namespace bead::explain {
namespace {

// The finite pairs, mean removed.
void Centred(const std::vector<double>& a, const std::vector<double>* b, std::vector<double>& ca,
             std::vector<double>& cb) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i]) || (b && !std::isfinite((*b)[i]))) continue;
    ca.push_back(a[i]);
    if (b) cb.push_back((*b)[i]);
  }
  auto centre = [](std::vector<double>& v) {
    if (v.empty()) return;
    double m = 0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double& x : v) x -= m;
  };
  centre(ca);
  centre(cb);
}

// Biased cross-covariance sum_i a[i + k] b[i] / N, k may be negative.
double Covariance(const std::vector<double>& a, const std::vector<double>& b, long k) {
  const long n = static_cast<long>(a.size());
  double s = 0;
  for (long i = std::max(0L, -k); i < n && i + k < n; ++i) s += a[i + k] * b[i];
  return s / static_cast<double>(n);
}

}  // namespace

double NormalQuantile(double p) {
  // Acklam's algorithm: rational approximations in the centre and the tails.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (p <= 0) return -INFINITY;
  if (p >= 1) return INFINITY;
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - 0.02425) return -NormalQuantile(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

double StudentTQuantile(double p, int dof) {
  const double z = NormalQuantile(p), v = std::max(dof, 1), z2 = z * z;
  return z + z * (z2 + 1) / (4 * v) + z * ((5 * z2 + 16) * z2 + 3) / (96 * v * v) +
         z * (((3 * z2 + 19) * z2 + 17) * z2 - 15) / (384 * v * v * v);
}

double ChiSquareQuantile(double p, int dof) {
  // Wilson-Hilferty: (X/k)^(1/3) is nearly normal with mean 1 - 2/(9k), variance 2/(9k).
  const double k = dof, z = NormalQuantile(p), v = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - v + z * std::sqrt(v), 3.0);
}

Whiteness ResidualWhiteness(const std::vector<double>& e, int lags) {
  Whiteness w;
  std::vector<double> c, unused;
  Centred(e, nullptr, c, unused);
  const long n = static_cast<long>(c.size());
  w.lags = static_cast<int>(std::min<long>(lags, std::max(1L, n - 1)));
  if (n < 3) return w;
  const double r0 = Covariance(c, c, 0);
  w.bound = 2.58 / std::sqrt(static_cast<double>(n));
  for (int k = 1; k <= w.lags; ++k) {
    const double r = r0 > 0 ? Covariance(c, c, k) / r0 : 0.0;
    w.acf.push_back(r);
    w.chi2 += static_cast<double>(n) * r * r;
    w.outside += std::abs(r) > w.bound;
  }
  w.chi2_limit = ChiSquareQuantile(0.99, w.lags);
  w.white = w.chi2 < w.chi2_limit;
  return w;
}

InputCorrelation ResidualInputCorrelation(const std::vector<double>& e, const std::vector<double>& u, int lags) {
  InputCorrelation x;
  std::vector<double> ce, cu;
  if (u.size() != e.size()) return x;
  Centred(e, &u, ce, cu);
  const long n = static_cast<long>(ce.size());
  x.lags = static_cast<int>(std::min<long>(lags, std::max(1L, n - 1)));
  if (n < 3) return x;
  const double norm = std::sqrt(Covariance(ce, ce, 0) * Covariance(cu, cu, 0));
  x.bound = 2.58 / std::sqrt(static_cast<double>(n));
  for (int k = -x.lags; k <= x.lags; ++k) {
    const double r = norm > 0 ? Covariance(ce, cu, k) / norm : 0.0;
    x.ccf.push_back(r);
    x.outside += std::abs(r) > x.bound;
  }
  x.independent = x.outside == 0;
  return x;
}

Spectrum ResidualSpectrum(const std::vector<double>& t, const std::vector<double>& e, double max_hz, int max_peaks) {
  Spectrum s;
  std::vector<double> ts, es;
  for (std::size_t i = 0; i < e.size() && i < t.size(); ++i)
    if (std::isfinite(e[i]) && std::isfinite(t[i])) ts.push_back(t[i]), es.push_back(e[i]);
  const std::size_t n = es.size();
  if (n < 16) return s;
  double mean = 0, var = 0;
  for (double v : es) mean += v;
  mean /= static_cast<double>(n);
  for (double& v : es) v -= mean, var += v * v;
  var /= static_cast<double>(n - 1);
  const double span = ts.back() - ts.front();
  if (!(span > 0) || !(var > 0)) return s;
  // Frequencies from 1/(4 span) to the mean Nyquist, four per independent one.
  const double f_nyq = 0.5 * static_cast<double>(n - 1) / span;
  const double df = 1.0 / (4.0 * span);
  const auto nf = static_cast<std::size_t>(std::min(f_nyq, max_hz) / df);
  // Scargle's sums through Fourier sums at the uneven times (Press &
  // Rybicki, ApJ 338, 1989, eqs. 5-9: tau, and the sums of cos^2 and sin^2,
  // from Sum exp(2 i w t)): Y(w) = Sum e_i exp(i w t_i), W(2w) = Sum
  // exp(2 i w t_i), with t from the first sample (the periodogram does not
  // depend on where time starts). O(n + nf log nf): an hour of profiles
  // (720000 samples, 288000 frequencies) in about a second and a 64 MB grid,
  // where the direct sums took hours.
  std::vector<double> x(n), ones(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) x[i] = 2.0 * std::numbers::pi * df * (ts[i] - ts.front());
  const FourierSums sums = UnevenFourierSums(x, es, ones, 2 * nf);
  const double nn = static_cast<double>(n);
  for (std::size_t j = 1; j <= nf; ++j) {
    const std::complex<double> w2 = sums.b[2 * j];  // Sum cos 2wt + i Sum sin 2wt
    const double two_w_tau = std::atan2(w2.imag(), w2.real());
    const std::complex<double> z = sums.a[j] * std::polar(1.0, -0.5 * two_w_tau);
    const double yc = z.real(), ys = z.imag();
    // Sum cos^2 w(t - tau) = n/2 + |W|/2, Sum sin^2 = n/2 - |W|/2; a sum
    // within the Fourier sums' rounding of 0 (evenly sampled at exactly
    // the Nyquist rate) carries no power.
    const double cc = 0.5 * (nn + std::abs(w2)), ss = 0.5 * (nn - std::abs(w2));
    const double floor = 1e-9 * nn;
    s.frequency_hz.push_back(df * static_cast<double>(j));
    s.power.push_back(0.5 * ((cc > floor ? yc * yc / cc : 0) + (ss > floor ? ys * ys / ss : 0)) / var);
  }
  // Local maxima, significance with F = the number of independent frequencies.
  const double independent = std::max(1.0, f_nyq * span);
  for (std::size_t j = 1; j + 1 < s.power.size(); ++j) {
    const double p = s.power[j];
    if (!(p > s.power[j - 1] && p >= s.power[j + 1])) continue;
    const double fap = 1.0 - std::pow(1.0 - std::exp(-p), independent);
    if (fap < 0.01) s.peaks.push_back({s.frequency_hz[j], p, fap});
  }
  std::sort(s.peaks.begin(), s.peaks.end(), [](const auto& a, const auto& b) { return a.power > b.power; });
  if (s.peaks.size() > static_cast<std::size_t>(max_peaks)) s.peaks.resize(static_cast<std::size_t>(max_peaks));
  return s;
}

}  // namespace bead::explain
