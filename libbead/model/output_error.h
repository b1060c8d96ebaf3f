// The output-error search of identify.cc: the denominator's search
// parameters, and its refinement (with the delay) by Ceres over the
// projected output error of projection.h. Internal to libbead/model.
#pragma once

#include <complex>
#include <limits>
#include <vector>

#include "libbead/model/identify.h"
#include "libbead/model/projection.h"

namespace bead::model {

std::vector<std::complex<double>> Roots(const std::vector<double>& den);
std::vector<double> FromRoots(const std::vector<std::complex<double>>& roots);

// The search's parameters for a denominator: the logs of its coefficients
// (any transfer function), or the log time constants of real poles (a process
// model). A start with poles in the right half plane is reflected into the
// left (as tfest does with its initial estimates); for a process model a
// complex pair becomes two real poles about its natural frequency.
// A pole slower than `slowest` (1 / the longest stretch) is put there: its
// free response would be a ramp the initial state could use as drift.
std::vector<double> ToSearch(const std::vector<double>& den, bool real_poles, double slowest);
std::vector<double> FromSearch(const double* theta, int n, bool real_poles);

struct Refined {
  std::vector<double> den, theta;
  double delay = 0.0, loss = std::numeric_limits<double>::infinity();
};

// Refines the denominator (search parameters `theta`) and, unless the
// options fix it, the delay (held to [lo, hi]) from the given start; `dt`
// is the sample step (the delay's difference step is 2 % of it). The loss
// is the mean squared projected output error (infinite when unstable).
Refined Refine(const ProjectionProblem& problem, const IdentifyOptions& o, std::vector<double> theta, double delay,
               double lo, double hi, double dt, double slowest);

}  // namespace bead::model
