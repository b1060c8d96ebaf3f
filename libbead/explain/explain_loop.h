// The loop that closes the model: diagnose the residual, try every effect
// of the catalogue the data supports, keep the one that helps most, and
// repeat. The base model's gain, operating point and delay are refitted
// with every candidate and without it (they are never effects), so an
// effect must beat the base model at its best. No overfitting: an effect
// is kept only when
//  1. fitted on the estimation half of the record (every other of
//     `blocks` time blocks; the whole record when another run is the
//     held-out data) it lowers the BIC there, and
//  2. on the held-out blocks (or on another run, when given) it lowers the
//     squared error significantly: F = (drop in SSE per added parameter) /
//     (SSE left per effective sample, N_eff from the residual's lag-one
//     correlation) above the chi-square quantile at level alpha / K, K the
//     candidates tried in the round (Bonferroni: at most alpha of adding a
//     false effect per round); a
//     periodic term must also beat the same term fitted to its part turning
//     at other rates (surrogates, which a coloured residual fits too);
//  3. it passes the same held-out test against the base model with a
//     linear correction of its dynamics (SeriesData::dynamics) added to
//     both sides: what a better linear model would explain is not an
//     effect. When that correction is itself significant the base model is
//     misspecified, and the report says so.
// Kept effects are refitted on the whole record for the report, each
// parameter with a 95 % interval from the sandwich covariance under the
// residual's own AR noise model (parameter_covariance.h); pairs whose
// estimates correlate beyond 0.9 are reported as confounded, in words.
// Afterwards, every significant peak left in the residual spectrum is
// checked against the rotating parts (their mean rate and first two
// harmonics) and reported as unexplained with what it tracks.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "libbead/explain/diagnostics.h"
#include "libbead/explain/effects.h"
#include "libbead/explain/series_data.h"
#include "libbead/explain/shift_profile.h"

namespace bead::explain {

struct FittedParameter {
  std::string name;
  double value = 0.0, ci95 = 0.0;  // value +- ci95
};

struct AddedEffect {
  std::string name, description, tracks;
  std::vector<FittedParameter> parameters;
  double fit_before_pct = 0, fit_after_pct = 0, rms_before = 0, rms_after = 0;
  double bic_drop = 0;   // on the estimation blocks
  double heldout_f = 0;  // F on the held-out data
};

struct Candidate {  // every effect tried in a round, for the diagnostics
  int round = 0;
  std::string name;
  double bic_drop = 0, heldout_f = 0;
  double surrogate_f = 0;  // periodic terms: the largest surrogate's F (NaN: not tried)
  double guarded_f = 0;    // F against the base with its dynamics corrected (NaN: not tried)
  bool accepted = false;
};

struct Unexplained {
  std::string what;    // "periodic" or "correlated residual"
  std::string tracks;  // "wheel at the nozzle x1", "frequency 3.10 Hz", ...
  double frequency_hz = 0, power = 0, false_alarm = 1;
};

// The residual of a model and what it shows.
struct Diagnosis {
  std::vector<double> residual;  // y - prediction, per sample
  double fit_pct = 0, rms = 0;   // MATLAB compare's fit %, RMS error
  Whiteness whiteness;
  InputCorrelation input;
  Spectrum spectrum;
};

struct ExplainOptions {
  CatalogueOptions catalogue;
  int blocks = 20;
  double alpha = 0.01;
  int max_effects = 5;
  int lags = 25;
  double spectrum_max_hz = 20.0;
  const SeriesData* validation = nullptr;  // another run: held-out data instead of the blocks
};

// The base model's dynamics against a linear correction of them.
struct BaseAdequacy {
  bool tested = false;
  double heldout_f = 0.0, threshold = 0.0;   // the correction's held-out F and the level it had to beat
  double rms_before = 0.0, rms_after = 0.0;  // held-out RMS without and with the correction
  bool misspecified = false;
};

// Two parameters the data cannot tell apart: their estimates' correlation
// is this close to +-1, so one's error is taken up by the other and each
// interval holds only with the other free (the intervals printed are so).
struct Confounding {
  std::string first, second;  // "effect.parameter"
  double correlation = 0.0;
  std::string note;  // what it means, in words
};

struct ExplainReport {
  std::vector<AddedEffect> effects_added;
  std::vector<AddedEffect> base_refit;  // the base model's gain, operating point and delay, refitted
  BaseAdequacy base;
  ShiftProfile shift_profile;
  std::vector<Candidate> candidates;
  std::vector<Unexplained> unexplained;
  Diagnosis before, after;  // the base model alone, and with the effects kept
  // The wheel-position shift that best aligns the data (whether or not it
  // was kept as an effect), with its 95 % interval; NaN without a wheel.
  double position_shift_counts = 0,
         position_shift_ci95_counts = 0;  // half-width: the larger side; infinite: not pinned
  bool position_shift_estimated = false;
  // The shift's correlation with the base model's delay in the joint fit
  // at the best shift (NaN: not estimated): near +-1 at a steady wheel speed.
  double shift_delay_correlation = NAN;
  std::vector<Confounding> confounded;
  // The final set, for re-evaluating it on other data (corrected_flow.h):
  // the base model's refit terms first (base_terms of them), then the effects kept.
  std::vector<Effect> final_effects;
  std::vector<std::vector<double>> final_params;
  std::size_t base_terms = 0;
  // The final set's parameter covariance, flattened over its (effect,
  // parameter) slots in order; NaN where a parameter is not pinned.
  std::vector<double> final_covariance;
};

ExplainReport Explain(const SeriesData& data, const ExplainOptions& options = {});

}  // namespace bead::explain
