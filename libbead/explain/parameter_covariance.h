// The covariance of a fitted effect set's parameters under the noise the
// residual really has: the sandwich (J'J)^-1 J' Sigma J (J'J)^-1 with J the
// Jacobian of the residual in every parameter (linear and nonlinear, the
// base model's refit included) and Sigma the covariance of the residual's
// own AR noise model (noise_model.h). On a white residual it is the usual
// s2 (J'J)^-1; on the smooth residual a flow model leaves it is many times
// wider, and unlike one N / N_eff factor for all it weighs the noise at
// the frequencies each parameter's column lives at: a slow drift term sees
// the noise's low-frequency power, a once-per-revolution term the power at
// the wheel's rate. Why this and not a kernel (Newey-West) estimate:
// docs/explain.md.
#pragma once

#include <utility>
#include <vector>

#include "libbead/explain/effect_fit.h"
#include "libbead/explain/noise_model.h"

namespace bead::explain {

struct ParameterCovariance {
  std::vector<std::vector<double>> sd;  // per effect and parameter; infinite: the data does not pin it
  std::vector<std::pair<std::size_t, std::size_t>> index;  // (effect, parameter) of each flattened slot
  std::vector<double> correlation;  // flattened [slot * slots + slot]; NaN where a side is not pinned
  // Per effect and parameter: the residual's long-run variance along the
  // parameter's profiled direction (its Jacobian column with the others
  // projected out), Var(theta) / (J'J)^-1: the scale of the profile
  // likelihood's 95 % threshold, SSE_min + chi2_1(0.95) q. NaN: not pinned.
  std::vector<std::vector<double>> variance_along;
  ArNoise noise;  // the residual's noise model (noise_model.h)

  double Correlation(std::size_t effect_a, std::size_t param_a, std::size_t effect_b, std::size_t param_b) const;
  // The covariance itself, flattened [slot * slots + slot] (NaN where a side
  // is not pinned): what ExplainReport::final_covariance holds.
  std::vector<double> Matrix() const;
};

ParameterCovariance Covariance(const SeriesData& d, const EffectSet& set, const std::vector<std::size_t>& rows);

}  // namespace bead::explain
