// A model's output on data it was not fitted to, and its fit % there
// (MATLAB's compare). Stretches where the process started
// (Segment::process_starts) begin from rest; the others' initial states
// are fitted to the output when it is given.
#pragma once

#include <vector>

#include "libbead/core/segment.h"
#include "libbead/model/transfer_function.h"

namespace bead::model {

// The model's output on other data: offset + G(s) u, with each segment's
// initial state fitted to y when y is given (as MATLAB's compare does by
// default), else each segment in steady state at its first input.
std::vector<double> Predict(const TransferFunction& tf, double offset, const std::vector<double>& t,
                            const std::vector<double>& u, const std::vector<double>& y,
                            const std::vector<Segment>& segments = {});

// Fit % of a model on other data (MATLAB compare, initial state estimated).
double ValidateFitPercent(const TransferFunction& tf, double offset, const std::vector<double>& t,
                          const std::vector<double>& u, const std::vector<double>& y,
                          const std::vector<Segment>& segments = {});

}  // namespace bead::model
