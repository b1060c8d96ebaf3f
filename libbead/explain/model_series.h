// SeriesData for measured data from anywhere: time, input and output
// columns (uneven sampling and gaps allowed) against a transfer function
// simulated on the data's own times. A gap longer than five median sample
// spacings is a stop: the time since the last (re)start feeds the build-up
// term, and the model restarts from rest there (the process was off).
#pragma once

#include <string>
#include <vector>

#include "libbead/explain/series_data.h"
#include "libbead/model/transfer_function.h"

namespace bead::explain {

SeriesData ModelSeries(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                       const model::TransferFunction& tf, const std::string& y_unit = "");

}  // namespace bead::explain
