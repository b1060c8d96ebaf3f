// The catalogue of effects a bead rig (or any process measured against a
// model) really shows. Each is a parametric term added to the model's
// prediction:
//
//   prediction = base(shifted) * (1 + sum of multiplicative terms) + sum of additive terms
//
// where `shifted` moves the data in wheel position (wrong encoder offset)
// or the model's input in time (latency, a delay that changes). A term is
// linear in its `linear` parameters; its `nonlinear` ones (a shift, a time
// constant) are searched on a grid, then refined with the rest by Ceres.
#pragma once

#include <string>
#include <vector>

#include "libbead/explain/series_data.h"

namespace bead::explain {

struct Effect {
  std::string name;                            // e.g. "once_per_rev[wheel at the nozzle]"
  std::string description;                     // what it stands for, one line
  std::string tracks;                          // the rotating part a periodic term follows ("" otherwise)
  std::vector<std::string> nonlinear, linear;  // parameter names, with units
  std::vector<std::vector<double>> grid;       // start grid of each nonlinear parameter
  enum class Kind { kPositionShift, kDelay, kDelayDrift, kDelayLevel, kMultiplicative, kAdditive } kind;
  // The columns of the linear parameters for given nonlinear ones: the
  // multiplicative terms' factors (times base) or the additive terms.
  std::vector<std::vector<double>> Columns(const SeriesData& data, const double* nonlinear_values) const;
  // The extra input delay per sample (kDelay, kDelayDrift, kDelayLevel) or the
  // position shift (kPositionShift) for given nonlinear values.
  double PositionShift(const double* nonlinear_values) const;
  bool IsDelay() const { return kind == Kind::kDelay || kind == Kind::kDelayDrift || kind == Kind::kDelayLevel; }
  void AddDelay(const SeriesData& data, const double* nonlinear_values, std::vector<double>& delay) const;

  // Which catalogued feature it is built from (set by the catalogue).
  int part = -1;     // index into data.parts for periodic terms
  int channel = -1;  // index into data.channels for a recorded channel's term (data.input_parts for "input_part")
  int harmonic = 1;
  std::string
      feature;  // "scale", "bias", "drift", "time_to_laser", "height", "buildup", "level", "dynamics", "channel", "input_part"
};

struct CatalogueOptions {
  bool has_wheel = false;              // position shifts make sense
  double position_range_counts = 0.0;  // offset search +- this
  double delay_range_s = 0.5;
};

// The effects this data can support: a periodic term only for a part whose
// phase is known and which turns at least twice in the record, a
// time-to-laser term only when that time varies, and so on.
std::vector<Effect> Catalogue(const SeriesData& data, const CatalogueOptions& options);

// The base model's own parameters, refitted with every candidate and never
// reported as effects: its gain (a factor), its operating point (a
// constant) and its delay (a time shift, where the data can be shifted).
std::vector<Effect> BaseRefit(const SeriesData& data, const CatalogueOptions& options);

// A linear correction of the base model's dynamics (SeriesData::dynamics);
// empty name when the data carries no such columns.
Effect DynamicsCorrection(const SeriesData& data);

}  // namespace bead::explain
