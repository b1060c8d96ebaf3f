// The building blocks of a continuous transfer function's response on
// measured time stamps, for identification by variable projection.
//
// For a monic denominator A(s) = s^n + a1 s^(n-1) + ... + an, the input
// held between samples (zero-order hold) and delayed by `delay_s`:
//   state[k](t)  = s^k / A(s) applied to the delayed input, k = 0..n-1,
//                  from zero state at the start of each segment;
//   free[k](t)   = the response of 1 / A(s) from the unit initial state e_k
//                  (no input), restarted at each segment's first sample;
//   delayed(t)   = the delayed held input itself.
// Any numerator N(s) = sum_k beta_k s^k (k <= n) gives the forced output
// sum_k beta_k s^k / A(s) u, and s^n / A(s) = 1 - sum_j a_(n-j) s^j / A(s),
// so the output is linear in beta, in the initial states and in a constant:
// that is what the identification solves by least squares at each trial
// denominator and delay.
//
// Exact for any sampling: between samples the state moves by the matrix
// exponential of the step, the input switching where the delayed input
// does (inside a sample interval for a fractional delay). The input before
// the first sample is `before` when given (0 for a record from rest), else
// the first sample's value (a record that starts in the middle of the
// process; the initial state covers the rest).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "libbead/core/segment.h"

namespace bead::model {

struct StateResponses {
  int n = 0;
  std::vector<std::vector<double>> state;  // n series, one value per sample (NaN outside the segments)
  std::vector<std::vector<double>> free;   // n series
  std::vector<double> delayed;             // the delayed held input at each sample
};

// `den` monic, descending powers of s (den[0] == 1); t increasing; the
// whole input record u (also outside the segments: the input's history).
StateResponses ComputeStateResponses(const std::vector<double>& den, double delay_s, const std::vector<double>& t,
                                     const std::vector<double>& u, const std::vector<Segment>& segments,
                                     std::optional<double> before = std::nullopt);

// True when every root of the monic `den` has a negative real part
// (Routh-Hurwitz for n <= 2, eigenvalues of the companion matrix above).
bool HurwitzStable(const std::vector<double>& den);

}  // namespace bead::model

namespace bead::model {

// A basis of linear filters of the input: the states of 1 / (s + p)^K
// (p: the geometric mean of the magnitudes of `den`'s roots, the model's
// own band) applied to the input delayed by `delay_s`, and that delayed
// input itself. Any strictly proper correction with poles at p, plus a
// direct term, is a combination of these K + 1 series.
std::vector<std::vector<double>> FilterBasis(const std::vector<double>& den, double delay_s,
                                             const std::vector<double>& t, const std::vector<double>& u,
                                             const std::vector<Segment>& segments, int K = 4);

}  // namespace bead::model
