// SeriesData for measured data from anywhere: time, input and output
// columns (uneven sampling and gaps allowed) against a transfer function
// with its operating point (y = offset + G(s) u), predicted on the data's
// own times, each stretch from steady state at its first input, with the
// model's free responses beside it (its initial state, refitted in the loop). Only the
// samples inside `segments` (where the process ran, series/process_on.h)
// are explained; the input's whole record drives the model. The time since
// each stretch began feeds the build-up term.
#pragma once

#include <string>
#include <vector>

#include "libbead/core/segment.h"
#include "libbead/explain/series_data.h"
#include "libbead/model/transfer_function.h"

namespace bead::explain {

// A base model's input after the first: its name, transfer function and
// record on the same times.
struct MoreInput {
  std::string name;
  model::TransferFunction tf;
  std::vector<double> u;
};

// With `more`, the base is offset + G(s) u + sum_k G_k(s) u_k (each part
// from steady state at its stretch's first input, its free response among
// the initial-state columns); the delay refit moves the first input's part
// only, and each other part's gain is refitted (SeriesData::input_parts).
SeriesData ModelSeries(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                       const model::TransferFunction& tf, double offset, const std::vector<Segment>& segments,
                       const std::string& y_unit = "", const std::vector<MoreInput>& more = {});

}  // namespace bead::explain
