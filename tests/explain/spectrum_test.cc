// The residual's periodogram, computed through fast Fourier sums, is
// Scargle's definition (ApJ 263, 1982, eq. 10) evaluated term by term, to
// 1e-8 of a power (the sums hold about 12 digits of sum |e|; a wrong sign,
// scale or index errs by O(1)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "libbead/explain/diagnostics.h"

namespace bead {
namespace {

constexpr double kPi = std::numbers::pi;

// Scargle's periodogram term by term, normalised by the variance.
std::vector<double> DirectLombScargle(const std::vector<double>& t, std::vector<double> e,
                                      const std::vector<double>& f_hz) {
  double mean = 0, var = 0;
  for (double v : e) mean += v;
  mean /= double(e.size());
  for (double& v : e) v -= mean, var += v * v;
  var /= double(e.size() - 1);
  std::vector<double> p;
  for (double f : f_hz) {
    const double w = 2 * kPi * f;
    double s2 = 0, c2 = 0;
    for (double ti : t) s2 += std::sin(2 * w * ti), c2 += std::cos(2 * w * ti);
    const double tau = std::atan2(s2, c2) / (2 * w);
    double yc = 0, ys = 0, cc = 0, ss = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double c = std::cos(w * (t[i] - tau)), s = std::sin(w * (t[i] - tau));
      yc += e[i] * c, ys += e[i] * s, cc += c * c, ss += s * s;
    }
    p.push_back(0.5 * (yc * yc / cc + ys * ys / ss) / var);
  }
  return p;
}

// Uneven times (200 Hz with dropped samples and jitter, starting far from
// zero as a log's clock does), a tone at 1.7 Hz in noise: every power is
// the definition's, and the strongest peak is the tone.
TEST(ResidualSpectrum, IsScarglesPeriodogram) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> t, e;
  for (int i = 0; i < 4000; ++i) {
    if (u(rng) < 0.1) continue;
    const double ti = 5000.0 + i / 200.0 + 1e-3 * u(rng);
    t.push_back(ti);
    e.push_back(0.5 * std::sin(2 * kPi * 1.7 * ti + 0.3) + noise(rng));
  }
  const explain::Spectrum s = explain::ResidualSpectrum(t, e, 20.0);
  ASSERT_GT(s.power.size(), 1000u);
  const std::vector<double> direct = DirectLombScargle(t, e, s.frequency_hz);
  // Powers are chi-square(2)/2 scaled: O(1), the tone's O(n a^2 / 4 var).
  for (std::size_t j = 0; j < direct.size(); ++j)
    ASSERT_NEAR(s.power[j], direct[j], 1e-8 * std::max(1.0, direct[j])) << s.frequency_hz[j];
  ASSERT_FALSE(s.peaks.empty());
  const double df = s.frequency_hz[0];
  EXPECT_NEAR(s.peaks[0].frequency_hz, 1.7, df);
}

}  // namespace
}  // namespace bead
