// Whether a designed loop may be handed to a user: stable, well posed, and
// with the robustness margins asked for. `bead tune` writes a controller
// only when this says yes; otherwise it refuses with the reasons.
//
// Well posed: with an ideal derivative (Tf = 0) on a plant with a direct
// feedthrough (as many zeros as poles, thesis eq. 22's form), the loop gain
// grows without bound with frequency: any unmodelled lag or delay makes it
// unstable, and with the model's own delay the characteristic
// quasi-polynomial is of advanced type (infinitely many roots in the right
// half plane). With a filter, L(inf) = g_inf (kp + kd / Tf) is finite: the
// loop is well posed when 1 + L(inf) != 0, and with a delay its roots'
// high-frequency chain lies left of the axis only when |L(inf)| < 1
// (the neutral chain of closed_loop.h).
#pragma once

#include <string>
#include <vector>

#include "libbead/control/controller_file.h"

namespace bead::control {

struct LoopRequirements {
  double min_degree = 0;         // J (1/s) must exceed this: the loop's rightmost root left of -min_degree
  double max_ms = 2.0;           // peak sensitivity
  double min_gain_margin = 1.5;  // the gain may rise by this factor before the loop is unstable
};

struct LoopVerdict {
  bool ok = false;
  // A stable loop that some smaller gain would destabilise (a -180 degree
  // crossing where |L| > 1): said, not refused, when the upper margin holds.
  bool conditionally_stable = false;
  double lower_gain_margin = 0;       // the factor the gain may fall by (0: none)
  double upper_gain_margin = 0;       // the factor it may rise by (inf: none)
  std::vector<std::string> failures;  // each a sentence: what fails and by how much
  std::string Summary() const;        // failures joined by "; "
};

// True when the plant has a direct feedthrough (deg num == deg den).
bool HasFeedthrough(const model::TransferFunction& plant);

LoopVerdict CheckLoop(const model::TransferFunction& plant, const Evaluated& e, const LoopRequirements& r = {});

}  // namespace bead::control
