// The fast Fourier sums at uneven positions are the direct sums: at the
// precision Gaussian gridding promises (Greengard & Lee 2004, M_sp = 12 at R = 2: about 12 digits of
// sum |c|), so 1e-9 of sum |c| leaves a thousandfold margin and still
// fails for any wrong sign, scale or index (those err by O(1)).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "libbead/series/fourier_sums.h"

namespace bead {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Fft, IsTheDirectTransform) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  std::vector<std::complex<double>> v(64);
  for (auto& c : v) c = {normal(rng), normal(rng)};
  std::vector<std::complex<double>> f = v;
  Fft(f, +1);
  for (std::size_t k = 0; k < v.size(); ++k) {
    std::complex<double> direct = 0;
    for (std::size_t m = 0; m < v.size(); ++m) direct += v[m] * std::polar(1.0, 2 * kPi * double(k * m) / 64.0);
    EXPECT_LT(std::abs(f[k] - direct), 1e-12 * 64) << k;
  }
  Fft(f, -1);
  for (std::size_t m = 0; m < v.size(); ++m) EXPECT_LT(std::abs(f[m] / 64.0 - v[m]), 1e-14 * 64) << m;
  std::vector<std::complex<double>> odd(48);
  EXPECT_THROW(Fft(odd, +1), std::exception);
}

TEST(UnevenFourierSums, AreTheDirectSums) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> where(-1.0, 7.0);  // outside [0, 2 pi) too: taken modulo
  std::normal_distribution<double> normal(0.5, 2.0);
  for (const std::size_t K : {0, 1, 37, 1000}) {
    const std::size_t n = 3000;
    std::vector<double> x(n), a(n), b(n);
    double scale = 0;
    for (std::size_t i = 0; i < n; ++i)
      x[i] = where(rng), a[i] = normal(rng), b[i] = normal(rng), scale += std::abs(a[i]) + std::abs(b[i]);
    const FourierSums f = UnevenFourierSums(x, a, b, K);
    ASSERT_EQ(f.a.size(), K + 1);
    for (std::size_t k = 0; k <= K; k += K / 20 + 1) {
      std::complex<double> da = 0, db = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const std::complex<double> e = std::polar(1.0, double(k) * x[i]);
        da += a[i] * e, db += b[i] * e;
      }
      EXPECT_LT(std::abs(f.a[k] - da), 1e-9 * scale) << "K " << K << " k " << k;
      EXPECT_LT(std::abs(f.b[k] - db), 1e-9 * scale) << "K " << K << " k " << k;
    }
  }
}

}  // namespace
}  // namespace bead
