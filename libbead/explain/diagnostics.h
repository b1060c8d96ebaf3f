// Residual diagnostics, as MATLAB's `resid` draws them (System
// Identification Toolbox; Ljung, System Identification, 1999, 16.6):
//  - whiteness: the autocorrelation r(k) = R(k)/R(0) of the residual for
//    lags 1..M against the 99 % band +-2.58/sqrt(N), and the portmanteau
//    statistic N sum r(k)^2, chi-square with M degrees of freedom for a
//    white residual;
//  - independence from the input: the cross-correlation of residual and
//    input for lags -M..M against the same band;
//  - the spectrum: a Lomb-Scargle periodogram (it takes uneven sampling
//    and gaps; Scargle, ApJ 263, 1982, eq. 10), normalised by the residual
//    variance, with the peaks whose false-alarm probability
//    1 - (1 - exp(-P))^F (F independent frequencies; Scargle eq. 14 with
//    Horne & Baliunas, ApJ 302, 1986, eq. 13) is below 1 %.
#pragma once

#include <vector>

namespace bead::explain {

struct Whiteness {
  int lags = 0;
  std::vector<double> acf;  // r(1..M)
  double bound = 0.0;       // 2.58 / sqrt(N)
  int outside = 0;          // lags outside the band
  double chi2 = 0.0;        // N sum r(k)^2
  double chi2_limit = 0.0;  // its 99 % quantile for M degrees of freedom
  bool white = false;       // chi2 below the limit
};

struct InputCorrelation {
  int lags = 0;
  std::vector<double> ccf;  // lags -M..M (index k + M)
  double bound = 0.0;
  int outside = 0;
  bool independent = false;  // no lag outside the band
};

struct SpectrumPeak {
  double frequency_hz = 0.0;
  double power = 0.0;        // normalised
  double false_alarm = 1.0;  // probability under white noise
};

struct Spectrum {
  std::vector<double> frequency_hz, power;
  std::vector<SpectrumPeak> peaks;  // significant, strongest first
};

// Finite samples only (NaN skipped, the rest taken in order).
Whiteness ResidualWhiteness(const std::vector<double>& e, int lags = 25);
InputCorrelation ResidualInputCorrelation(const std::vector<double>& e, const std::vector<double>& u, int lags = 25);
// Frequencies in steps of 1/(4 span) up to the smaller of max_hz and the
// mean Nyquist.
Spectrum ResidualSpectrum(const std::vector<double>& t, const std::vector<double>& e, double max_hz = 20.0,
                          int max_peaks = 5);

// The chi-square distribution's quantile (Wilson-Hilferty).
double ChiSquareQuantile(double p, int dof);
// Student's t quantile (Cornish-Fisher expansion about the normal one,
// Abramowitz & Stegun 26.7.5; within 1e-3 for dof >= 5).
double StudentTQuantile(double p, int dof);
// The standard normal quantile (Acklam's rational approximation, |error| < 1.2e-9).
double NormalQuantile(double p);

}  // namespace bead::explain
