// Model quality, as MATLAB's System Identification Toolbox defines it
// (compare, aic, fpe; Ljung, System Identification, 1999), for one output:
//   fit % = 100 (1 - ||y - yhat|| / ||y - mean(y)||)              (compare)
//   V     = (1/N) sum e^2                                           (loss function)
//   AIC   = N ln V + 2 np + N (ln(2 pi) + 1)                        (aic(..., 'aic'))
//   AICc  = AIC + 2 np (np + 1) / (N - np - 1)                      (aic(..., 'AICc'))
//   nAIC  = ln V + 2 np / N                                         (aic(...), the default)
//   BIC   = N ln V + N (ln(2 pi) + 1) + np ln N                     (aic(..., 'BIC'))
//   FPE   = V (1 + np / N) / (1 - np / N)                           (fpe)
// np: the number of estimated parameters; N: samples.
#pragma once

#include <vector>

namespace bead::model {

double FitPercent(const std::vector<double>& y, const std::vector<double>& yhat);

struct InformationCriteria {
  double loss = 0, aic = 0, aicc = 0, naic = 0, bic = 0, fpe = 0;
};

InformationCriteria Criteria(double loss, int samples, int parameters);
// From residuals (NaN residuals are skipped, and not counted in N).
InformationCriteria CriteriaFromResiduals(const std::vector<double>& residuals, int parameters);

}  // namespace bead::model
