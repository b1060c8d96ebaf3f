// What the data cannot tell apart, said in words (ExplainReport::confounded),
// and the offset the run implies: the loop's answers beside their
// intervals.
#pragma once

#include <vector>

#include "libbead/explain/effect_fit.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/parameter_covariance.h"

namespace bead::explain {

// Pairs of the final set's parameters whose estimates correlate beyond
// 0.9, at least one of them an effect's (the first base_terms are the base
// model's refit).
std::vector<Confounding> Confounded(const EffectSet& set, const ParameterCovariance& cov, std::size_t base_terms);

// `alt` passed in the round `kept` was added in; when it was never added
// after, and what the two explain correlates beyond 0.5, the report says
// the data cannot tell them apart.
void SayAlternative(const SeriesData& d, const Active& kept, const Active& alt, ExplainReport& report);

// The wheel-position shift: its profile (shift_profile.h) with the
// interval from the joint fit's covariance at the best shift, and the
// shift's correlation with the base model's delay.
void EstimateShift(const SeriesData& d, const EffectSet& current, const Effect& shift,
                   const std::vector<std::size_t>& rows, ExplainReport& report);

}  // namespace bead::explain
