// Whether an identified model has more structure than the data carry: a
// pole faster than the sampling can see, a pole and a zero that all but
// cancel, a steady-state gain whose sign the data contradict. Each is a
// model a controller design would take at its word (a time constant of
// 1e-10 s gives a PID that no actuator can follow), so identify says so
// and names the smaller structure that fits as well.
#pragma once

#include <string>
#include <vector>

#include "libbead/model/identify.h"

namespace bead::model {

struct Degeneracy {
  std::vector<std::string> findings;   // each a sentence with its numbers
  int drop_poles = 0, drop_zeros = 0;  // the smaller structure: this many fewer
  // The gain's sign is the data's opposite: a controller designed for the
  // model would push the wrong way, so no model file is written for it.
  bool wrong_sign = false;
  bool any() const { return !findings.empty(); }
};

// `t`, `u`, `y`: the fitted record (the gain's sign is tested by the
// slope of y on the input delayed by the model's delay, over `segments`).
Degeneracy FindDegeneracy(const IdentifiedModel& m, const std::vector<double>& t, const std::vector<double>& u,
                          const std::vector<double>& y, const std::vector<Segment>& segments = {});

// Why a model with these findings must not be used ("" when it may): a
// gain of the data's opposite sign, which a controller or a feed-forward
// built on it would push the wrong way. identify's file and bead.identify
// both refuse such a model with this reason.
std::string UnusableReason(const Degeneracy& d);

// The options of the smaller structure `d` names (poles and zeros
// lowered; a process model keeps its real poles). False when there is no
// smaller one (a single pole).
bool SmallerStructure(const IdentifyOptions& o, const Degeneracy& d, IdentifyOptions& smaller);

}  // namespace bead::model
