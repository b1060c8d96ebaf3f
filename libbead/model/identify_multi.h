// Identification with several inputs, as MATLAB's tfest with a
// multi-input data set: a transfer function per input, each with its own
// denominator and delay, one operating point,
//
//   y(t) = offset + sum_i G_i(s) u_i(t - delay_i) + free responses + e(t).
//
// By backfitting (Hastie & Tibshirani, Generalized Additive Models, 1990,
// section 4.3): each input's model is identified (identify.h: delay
// profile, output-error refinement, initial states) on the output less
// every other input's current part, in turn, until a sweep lowers the
// summed squared error by less than a part in 10^5 of it. Each sweep's
// numerators are the least-squares ones given the others, so the error
// never rises over a sweep; the fixed point is the joint output-error
// optimum over the numerators with the denominators and delays it found.
// Inputs that move together cannot be told apart: the report gives the
// largest correlation between two inputs, and warns beyond 0.9.
#pragma once

#include <string>
#include <vector>

#include "libbead/model/identify.h"

namespace bead::model {

struct MultiInputModel {
  bool ok = false;
  std::string reason;
  // Per input: its transfer function, process form, delay profile and its
  // part of the prediction (offset 0: the operating point is `offset`).
  std::vector<IdentifiedModel> inputs;
  double offset = 0.0;
  int parameters = 0;  // every input's poles, zeros + 1, delay and initial states, one offset
  double fit_percent = 0.0;
  std::size_t fitted_samples = 0;
  InformationCriteria criteria;
  std::vector<double> prediction;  // every sample (NaN outside the segments)
  int sweeps = 0;
  bool converged = false;
  double max_input_correlation = 0.0;  // the largest |correlation| between two inputs over the fitted samples
  std::string note;                    // what to say about it, if anything
};

// `u[i]` is input i's whole record on the output's times; `options[i]`
// its structure (poles, zeros, delay search). Every input's offset and
// initial-state flags follow options[0].
MultiInputModel IdentifyMultiInput(const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                                   const std::vector<double>& y, const std::vector<IdentifyOptions>& options,
                                   const std::vector<Segment>& segments = {}, int max_sweeps = 12);

// The model's output on other data (each input's part from steady state at
// its first input, as Predict does; initial states fitted to y when given).
std::vector<double> PredictMultiInput(const std::vector<TransferFunction>& tfs, double offset,
                                      const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                                      const std::vector<double>& y, const std::vector<Segment>& segments = {});

}  // namespace bead::model
