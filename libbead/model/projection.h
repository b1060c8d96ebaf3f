// The linear half of output-error identification (variable projection):
// for a trial monic denominator and delay, the numerator, the offset and
// each segment's initial free response solved by linear least squares over
// the fitted samples (lti_response.h gives the columns). And Young's
// state-variable-filter estimate of the denominator, the cheap linear fit
// that starts the search at each delay.
#pragma once

#include <optional>
#include <vector>

#include "libbead/model/lti_response.h"

namespace bead::model {

struct ProjectionProblem {
  const std::vector<double>* t = nullptr;  // the whole record
  const std::vector<double>* u = nullptr;
  const std::vector<double>* y = nullptr;
  std::vector<Segment> segments;
  std::vector<std::size_t> rows;  // fitted samples: inside the segments, y finite
  int zeros = 0;
  bool offset = true;
  bool initial_state = true;  // else: from rest, the input 0 before the record
};

struct Projection {
  bool ok = false;
  std::vector<double> num;  // descending powers of s
  double offset = 0.0;
  // Per segment (zeros where it starts from rest, Segment::process_starts):
  // the free response's value and first n-1 derivatives at
  // the segment's first sample (in the canonical form of lti_response.h the
  // free output is e_0' exp(A t) gamma, and e_0' A^k = e_k' for k < n).
  std::vector<std::vector<double>> free_response;
  double sse = 0.0;                // over the rows
  std::vector<double> residual;    // per row (with want_residual)
  std::vector<double> prediction;  // every sample, NaN outside the segments (with want_prediction)
};

Projection Project(const ProjectionProblem& p, const std::vector<double>& den, double delay_s,
                   bool want_residual = false, bool want_prediction = false);

// The state-variable-filter estimate of the monic denominator (n + 1
// coefficients) at a given delay, with a constant term, from filtered
// signals computed once (SvfSignals). nullopt when the least squares fails.
struct SvfSignals {
  int n = 0, m = 0;
  double lambda = 0.0, half_step = 0.0;
  std::vector<std::vector<double>> yf, uf;  // s^k F(s) y (per segment), s^k F(s) u (whole record)
};
SvfSignals FilterForSvf(const ProjectionProblem& p, int poles, double lambda, double dt);
struct SvfEstimate {
  std::vector<double> den;
  double equation_loss = 0.0;  // mean square of the filtered equation's residual
};
std::optional<SvfEstimate> SvfDenominator(const ProjectionProblem& p, const SvfSignals& s, double delay_s);

}  // namespace bead::model
