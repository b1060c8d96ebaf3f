#include "libbead/series/savgol.h"

#include <Eigen/Dense>
#include <cmath>

#include "libbead/core/error.h"

namespace bead {

SavgolMode ParseSavgolMode(const std::string& name) {
  if (name == "interp") return SavgolMode::kInterp;
  if (name == "mirror") return SavgolMode::kMirror;
  if (name == "nearest") return SavgolMode::kNearest;
  if (name == "constant") return SavgolMode::kConstant;
  if (name == "wrap") return SavgolMode::kWrap;
  throw Error("Savitzky-Golay mode '" + name + "' is not one of interp, mirror, nearest, constant, wrap");
}

std::vector<double> SavgolWeights(int window, int order, int deriv, double delta, double pos) {
  if (window < 1 || order < 0 || order >= window) throw Error("Savitzky-Golay: need 0 <= order < window");
  if (deriv < 0) throw Error("Savitzky-Golay: derivative order must be >= 0");
  std::vector<double> w(static_cast<std::size_t>(window), 0.0);
  if (deriv > order) return w;
  const double scale = std::max(1.0, (window - 1) / 2.0);
  // Vandermonde in t = (j - pos) / scale: value of the fit at t = 0 and its
  // derivatives are the coefficients times k! / scale^k.
  Eigen::MatrixXd a(window, order + 1);
  for (int j = 0; j < window; ++j) {
    const double t = (j - pos) / scale;
    double p = 1.0;
    for (int k = 0; k <= order; ++k, p *= t) a(j, k) = p;
  }
  // Row `deriv` of the pseudo-inverse: solve A^T-style via QR of A.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  Eigen::MatrixXd pinv = qr.solve(Eigen::MatrixXd::Identity(window, window));
  double factor = 1.0;
  for (int k = 2; k <= deriv; ++k) factor *= k;
  factor /= std::pow(scale * delta, deriv);
  for (int j = 0; j < window; ++j) w[static_cast<std::size_t>(j)] = factor * pinv(deriv, j);
  return w;
}

std::vector<double> SavgolFilter(const std::vector<double>& x, const SavgolOptions& o) {
  if (o.window % 2 == 0 || o.window < 1)
    throw Error("Savitzky-Golay: the window must be odd, got " + std::to_string(o.window));
  if (o.order >= o.window) throw Error("Savitzky-Golay: the order must be less than the window");
  const long n = static_cast<long>(x.size());
  const long half = o.window / 2;
  if (o.mode == SavgolMode::kInterp && n < o.window)
    throw Error("Savitzky-Golay: interp mode needs at least window (" + std::to_string(o.window) + ") samples, got " +
                std::to_string(n));
  std::vector<double> y(x.size(), 0.0);
  if (n == 0) return y;
  const std::vector<double> w = SavgolWeights(o.window, o.order, o.deriv, o.delta, static_cast<double>(half));
  auto sample = [&](long i) -> double {
    if (i >= 0 && i < n) return x[static_cast<std::size_t>(i)];
    switch (o.mode) {
      case SavgolMode::kMirror: {
        if (n == 1) return x[0];
        const long period = 2 * (n - 1);
        long m = ((i % period) + period) % period;
        if (m >= n) m = period - m;
        return x[static_cast<std::size_t>(m)];
      }
      case SavgolMode::kNearest:
        return x[i < 0 ? 0 : static_cast<std::size_t>(n - 1)];
      case SavgolMode::kWrap:
        return x[static_cast<std::size_t>(((i % n) + n) % n)];
      case SavgolMode::kConstant:
      case SavgolMode::kInterp:
        return o.cval;
    }
    return 0.0;
  };
  for (long i = 0; i < n; ++i) {
    double acc = 0.0;
    for (long j = 0; j < o.window; ++j) acc += w[static_cast<std::size_t>(j)] * sample(i - half + j);
    y[static_cast<std::size_t>(i)] = acc;
  }
  if (o.mode == SavgolMode::kInterp) {
    // The ends: the polynomial fitted to the first / last window samples.
    for (long p = 0; p < half; ++p) {
      const std::vector<double> head = SavgolWeights(o.window, o.order, o.deriv, o.delta, static_cast<double>(p));
      const std::vector<double> tail =
          SavgolWeights(o.window, o.order, o.deriv, o.delta, static_cast<double>(o.window - 1 - p));
      double a = 0.0, b = 0.0;
      for (long j = 0; j < o.window; ++j) {
        a += head[static_cast<std::size_t>(j)] * x[static_cast<std::size_t>(j)];
        b += tail[static_cast<std::size_t>(j)] * x[static_cast<std::size_t>(n - o.window + j)];
      }
      y[static_cast<std::size_t>(p)] = a;
      y[static_cast<std::size_t>(n - 1 - p)] = b;
    }
  }
  return y;
}

std::vector<double> SavgolFilterGaps(const std::vector<double>& x, const SavgolOptions& o, int max_fill) {
  const std::size_t n = x.size();
  std::vector<double> y(n, std::nan(""));
  std::size_t i = 0;
  while (i < n) {
    // A piece: from a finite sample up to the next gap longer than max_fill.
    while (i < n && std::isnan(x[i])) ++i;
    if (i >= n) break;
    std::vector<double> piece = {x[i]};
    std::size_t last_finite = i, end = i + 1;
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!std::isnan(x[j])) {
        const std::size_t gap = j - last_finite - 1;
        if (gap > static_cast<std::size_t>(max_fill)) break;
        for (std::size_t g = 1; g <= gap; ++g)  // linear fill of a short gap
          piece.push_back(x[last_finite] +
                          (x[j] - x[last_finite]) * static_cast<double>(g) / static_cast<double>(gap + 1));
        piece.push_back(x[j]);
        last_finite = j;
        end = j + 1;
      }
    }
    SavgolOptions po = o;
    if (static_cast<int>(piece.size()) < po.window && po.mode == SavgolMode::kInterp) {
      po.window =
          static_cast<int>(piece.size()) % 2 ? static_cast<int>(piece.size()) : static_cast<int>(piece.size()) - 1;
      po.order = std::min(po.order, po.window - 1);
    }
    const std::vector<double> f = po.window >= 1 ? SavgolFilter(piece, po) : piece;
    for (std::size_t j = 0; j < piece.size(); ++j)
      if (!std::isnan(x[i + j])) y[i + j] = f[j];
    i = end;
  }
  return y;
}

}  // namespace bead
