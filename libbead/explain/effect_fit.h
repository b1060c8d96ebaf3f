// Fitting a set of effects (effects.h) to a series: the prediction
//   base(shifted) * (1 + sum of multiplicative terms) + sum of additive terms,
// the linear parameters solved by least squares at every trial of the
// nonlinear ones (variable projection), the nonlinear ones by Ceres within
// their search grid (their intervals: parameter_covariance.h).
#pragma once

#include <vector>

#include "libbead/explain/effects.h"
#include "libbead/explain/series_data.h"

namespace bead::explain {

struct Active {
  Effect effect;
  std::vector<double> params;  // nonlinear..., linear...
  std::size_t nl() const { return effect.nonlinear.size(); }
};
using EffectSet = std::vector<Active>;

Active Activate(const Effect& e);
std::size_t ParameterCount(const EffectSet& set);

// Measured (possibly shifted) y and the set's prediction.
void Evaluate(const SeriesData& d, const EffectSet& set, std::vector<double>& y, std::vector<double>& pred);
std::vector<double> Residual(const SeriesData& d, const EffectSet& set);
// Sum of squares over the finite residuals of `rows`, scaled to all of them.
double Sse(const std::vector<double>& r, const std::vector<std::size_t>& rows);

// The newest effect's nonlinear start from its grid (linear ones solved at
// each point), then every nonlinear parameter refined together.
void Fit(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows, std::size_t first_free = 0);
// Refines what the set holds (no grid search): the nonlinear parameters of
// the effects from `first_free` on (the earlier ones held).
void Refine(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows, int max_iterations = 30,
            std::size_t first_free = 0);
// The linear parameters alone, for the nonlinear ones held.
void SolveLinear(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows);

// The linear parameters of the additive effects built from `feature`
// alone, the rest held (an initial state is local: the held-out test
// re-solves it on the held-out samples for both sides).
void SolveLinearOf(const SeriesData& d, EffectSet& set, const std::vector<std::size_t>& rows,
                   const std::string& feature);

double LagOneCorrelation(const std::vector<double>& r);

}  // namespace bead::explain
