#include "libbead/model/fit_metrics.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace bead::model {

double FitPercent(const std::vector<double>& y, const std::vector<double>& yhat) {
  double mean = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (std::isfinite(y[i]) && std::isfinite(yhat[i])) mean += y[i], ++n;
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  mean /= static_cast<double>(n);
  double err = 0, spread = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i]) || !std::isfinite(yhat[i])) continue;
    err += (y[i] - yhat[i]) * (y[i] - yhat[i]);
    spread += (y[i] - mean) * (y[i] - mean);
  }
  return 100.0 * (1.0 - std::sqrt(err / spread));
}

InformationCriteria Criteria(double v, int n, int np) {
  InformationCriteria c;
  const double N = n, p = np;
  const double constant = N * (std::log(2 * std::numbers::pi) + 1);
  c.loss = v;
  c.aic = N * std::log(v) + 2 * p + constant;
  c.aicc = n > np + 1 ? c.aic + 2 * p * (p + 1) / (N - p - 1) : std::numeric_limits<double>::infinity();
  c.naic = std::log(v) + 2 * p / N;
  c.bic = N * std::log(v) + constant + p * std::log(N);
  c.fpe = n > np ? v * (1 + p / N) / (1 - p / N) : std::numeric_limits<double>::infinity();
  return c;
}

InformationCriteria CriteriaFromResiduals(const std::vector<double>& e, int np) {
  double ss = 0;
  int n = 0;
  for (double r : e)
    if (std::isfinite(r)) ss += r * r, ++n;
  return Criteria(ss / std::max(n, 1), n, np);
}

}  // namespace bead::model
