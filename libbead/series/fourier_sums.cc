#include "libbead/series/fourier_sums.h"

#include <cmath>
#include <numbers>
#include <utility>

#include "libbead/core/error.h"

namespace bead {

void Fft(std::vector<std::complex<double>>& v, int sign) {
  const std::size_t n = v.size();
  if (n < 2) return;
  if (n & (n - 1)) throw Error("FFT: length " + std::to_string(n) + " is not a power of two");
  for (std::size_t i = 1, j = 0; i < n; ++i) {  // bit-reversed order
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(v[i], v[j]);
  }
  // Twiddles exp(sign 2 pi i m / n), each from its own cos and sin (no
  // recurrence: no error growing along the table).
  std::vector<std::complex<double>> w(n / 2);
  for (std::size_t m = 0; m < n / 2; ++m)
    w[m] = std::polar(1.0, sign * 2.0 * std::numbers::pi * static_cast<double>(m) / static_cast<double>(n));
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const std::size_t half = len / 2, step = n / len;
    for (std::size_t start = 0; start < n; start += len)
      for (std::size_t k = 0; k < half; ++k) {
        const std::complex<double> u = v[start + k], t = v[start + k + half] * w[k * step];
        v[start + k] = u + t;
        v[start + k + half] = u - t;
      }
  }
}

FourierSums UnevenFourierSums(const std::vector<double>& x, const std::vector<double>& ca,
                              const std::vector<double>& cb, std::size_t K) {
  if (ca.size() != x.size() || cb.size() != x.size())
    throw Error("Fourier sums: " + std::to_string(x.size()) + " positions but " + std::to_string(ca.size()) + " and " +
                std::to_string(cb.size()) + " coefficients");
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  constexpr int kSpread = 12;  // M_sp (Greengard & Lee, table 1: 12 digits at R = 2)
  // Grid: R = 2 times the M modes that cover -K-1 .. K.
  std::size_t grid_size = 64;
  while (grid_size < 2 * (2 * K + 2)) grid_size <<= 1;
  const double modes = static_cast<double>(grid_size) / 2.0;
  const double tau = std::numbers::pi * kSpread / (modes * modes * 2.0 * 1.5);  // eq. 10, R = 2
  const double h = kTwoPi / static_cast<double>(grid_size);
  std::vector<double> e3(kSpread + 1);
  for (int l = 0; l <= kSpread; ++l) e3[l] = std::exp(-(l * h) * (l * h) / (4.0 * tau));

  // Spreading: g(x) = sum_i c_i exp(-(x - x_i)^2 / (4 tau)), periodic, on
  // the grid; exp(-(d + l h)^2 / 4 tau) = E1 E2^l e3[|l|] with d the
  // distance from the grid point below (fast Gaussian gridding).
  std::vector<std::complex<double>> grid(grid_size);
  const auto g = static_cast<long long>(grid_size);
  for (std::size_t i = 0; i < x.size(); ++i) {
    double xi = std::fmod(x[i], kTwoPi);
    if (xi < 0) xi += kTwoPi;
    const auto m0 = static_cast<long long>(std::floor(xi / h));
    const double d = static_cast<double>(m0) * h - xi;  // in (-h, 0]
    const double e1 = std::exp(-d * d / (4.0 * tau)), e2 = std::exp(-d * h / (2.0 * tau));
    const std::complex<double> c(ca[i], cb[i]);
    double up = e1, down = e1 / e2;
    for (int l = 0; l <= kSpread; ++l, up *= e2)
      grid[static_cast<std::size_t>(((m0 + l) % g + g) % g)] += c * (up * e3[l]);
    for (int l = 1; l <= kSpread; ++l, down /= e2)
      grid[static_cast<std::size_t>(((m0 - l) % g + g) % g)] += c * (down * e3[l]);
  }
  Fft(grid, +1);
  // Deconvolution by the Gaussian's Fourier coefficient sqrt(tau / pi)
  // exp(-tau k^2); the two real sets apart by the transform's symmetry.
  FourierSums out;
  out.a.resize(K + 1), out.b.resize(K + 1);
  const double norm = std::sqrt(std::numbers::pi / tau) / static_cast<double>(grid_size);
  for (std::size_t k = 0; k <= K; ++k) {
    const std::complex<double> hk = grid[k], hm = std::conj(grid[(grid_size - k) % grid_size]);
    const double scale = norm * std::exp(tau * static_cast<double>(k) * static_cast<double>(k));
    out.a[k] = 0.5 * (hk + hm) * scale;
    out.b[k] = std::complex<double>(0.0, -0.5) * (hk - hm) * scale;
  }
  return out;
}

}  // namespace bead
