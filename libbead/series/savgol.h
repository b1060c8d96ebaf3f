// Savitzky-Golay smoothing and derivatives with SciPy `savgol_filter`
// semantics: odd window, polynomial order < window, derivative `deriv`
// scaled by 1 / delta^deriv, and the modes
//   interp   (default) the interior by the filter; the first and last
//            window/2 samples from a polynomial fitted to the first and
//            last window samples;
//   mirror   reflect about the end samples (d c b | a b c d | c b a);
//   nearest  repeat the end samples;
//   constant pad with cval;
//   wrap     periodic.
// Coefficients come from a QR least-squares fit on positions scaled to
// [-1, 1], so long windows and high orders stay well conditioned.
#pragma once

#include <string>
#include <vector>

namespace bead {

enum class SavgolMode { kInterp, kMirror, kNearest, kConstant, kWrap };

// Parses "interp", "mirror", ...; throws bead::Error otherwise.
SavgolMode ParseSavgolMode(const std::string& name);

struct SavgolOptions {
  int window = 5;
  int order = 2;
  int deriv = 0;
  double delta = 1.0;  // sample spacing, for derivatives
  SavgolMode mode = SavgolMode::kInterp;
  double cval = 0.0;
};

// Weights w[j], j = 0..window-1, such that sum_j w[j] x[j] is the deriv-th
// derivative at window position `pos` of the polynomial fitted to x.
std::vector<double> SavgolWeights(int window, int order, int deriv, double delta, double pos);

// Throws bead::Error for an even window, order >= window, or a series
// shorter than the window in interp mode.
std::vector<double> SavgolFilter(const std::vector<double>& x, const SavgolOptions& options);

// For series with gaps (NaN): gaps up to `max_fill` samples are filled by
// linear interpolation for the filter and NaN again in the output; longer
// gaps split the series, and each piece is filtered on its own (pieces
// shorter than the window are fitted with the highest order they allow).
// NaN never spreads beyond the samples that were NaN.
std::vector<double> SavgolFilterGaps(const std::vector<double>& x, const SavgolOptions& options, int max_fill);

}  // namespace bead
