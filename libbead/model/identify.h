// Identification of a continuous-time transfer function with n poles, m
// zeros and an input delay from sampled input/output data (even or uneven
// sampling), by output-error least squares:
//  1. a linear start from a state-variable filter: both signals filtered
//     by lambda^n / (s + lambda)^n and their derivatives (s^k times that),
//     then the coefficients of s^n y + a1 s^(n-1) y + ... = b0 s^m u + ...
//     by least squares (Young's SVF);
//  2. the delay: the loss is multi-modal in it, so a grid over
//     [0, max_delay], scoring each SVF start by its simulated output;
//  3. Ceres refines all coefficients and the delay on the simulation error
//     (y - simulated y), numeric derivatives;
//  4. only stable models (all poles in the left half plane) are accepted.
// The denominator is monic (s^n + ...); parameters np = n + m + 1 (+1 for
// an estimated delay).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "libbead/model/fit_metrics.h"
#include "libbead/model/transfer_function.h"

namespace bead::model {

struct IdentifyOptions {
  int poles = 2;
  int zeros = 1;
  std::optional<double> delay_s;  // fixed; none: estimated
  double max_delay_s = 1.0;
  int delay_grid = 41;
  double filter_rad_s = 0.0;      // SVF lambda; 0: from the sampling (2 pi / (20 dt))
  int max_iterations = 100;
};

struct IdentifiedModel {
  bool ok = false;
  std::string reason;
  TransferFunction tf;
  int parameters = 0;
  double fit_percent = 0;
  InformationCriteria criteria;
  std::vector<double> poles_real, poles_imag;
};

IdentifiedModel IdentifyTransferFunction(const std::vector<double>& t, const std::vector<double>& u,
                                         const std::vector<double>& y, const IdentifyOptions& options);

// Fit % of a model on other data (MATLAB compare).
double ValidateFitPercent(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u,
                          const std::vector<double>& y);

// Thesis Table 3: poles 1-3, zeros 0-2 (zeros <= poles), estimated on one
// data set and validated on another.
struct OrderRow {
  int poles, zeros;
  double fit_estimation, fit_validation, aicc;
  bool ok;
};
std::vector<OrderRow> OrderTable(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                                 const std::vector<double>& tv, const std::vector<double>& uv,
                                 const std::vector<double>& yv, IdentifyOptions options);

}  // namespace bead::model
