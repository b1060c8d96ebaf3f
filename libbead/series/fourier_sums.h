// Fourier sums at uneven sample positions, fast:
//   F(k) = sum_i c_i exp(i k x_i),  k = 0 .. K,  x_i in [0, 2 pi),
// for two real coefficient sets at once (a and b), in O(n + K log K)
// instead of the direct O(n K): a type-1 non-uniform FFT by Gaussian
// gridding (Greengard & Lee, "Accelerating the nonuniform fast Fourier
// transform", SIAM Review 46(3), 2004: the Gaussian of eq. 9 spread over
// 2 M_sp grid points, oversampling R = 2, tau of eq. 10 with M_sp = 12 for
// about 12 correct digits, and the fast gridding of section 3). The sums
// agree with the direct ones to about 1e-10 of sum |c_i| (tested).
// What the Lomb-Scargle periodogram of a long run needs (an hour at 200
// profiles/s: 720000 samples, 288000 frequencies).
#pragma once

#include <complex>
#include <cstddef>
#include <vector>

namespace bead {

struct FourierSums {
  std::vector<std::complex<double>> a, b;  // F_a(0..K), F_b(0..K)
};

// `x`, `ca`, `cb` of one length; x outside [0, 2 pi) is taken modulo 2 pi.
FourierSums UnevenFourierSums(const std::vector<double>& x, const std::vector<double>& ca,
                              const std::vector<double>& cb, std::size_t K);

// The in-place complex FFT of a power-of-two length (sign +1: sum of
// v_m exp(+2 pi i k m / N), unnormalised; -1: the forward transform).
void Fft(std::vector<std::complex<double>>& v, int sign);

}  // namespace bead
