#include "libbead/control/loop_check.h"

#include <cmath>
#include <cstdio>

#include "libbead/control/polynomial.h"

namespace bead::control {
namespace {

std::string Format(const char* fmt, double a, double b = 0) {
  char buf[500];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

// An ideal or filtered derivative on a plant with a direct feedthrough:
// improper (refused), or L(inf) = g_inf (kp + kd / Tf) said when it makes
// the loop ill-posed.
void CheckWellPosed(const model::TransferFunction& plant, const Pid& pid, LoopVerdict& v) {
  if (!HasFeedthrough(plant)) return;
  if (pid.kd != 0 && pid.tf_s <= 0) {
    v.failures.push_back(
        "the model has a direct feedthrough (as many zeros as poles) and the derivative is ideal: the loop gain "
        "grows without bound with frequency, so the loop is improper (with any delay, unstable); give --filter N, "
        "or identify a model with fewer zeros than poles");
    return;
  }
  const double g_inf = Leading(plant.num) / Leading(plant.den);
  const double l_inf = g_inf * (pid.kp + (pid.tf_s > 0 ? pid.kd / pid.tf_s : 0.0));
  if (std::abs(1.0 + l_inf) < 1e-9) {
    v.failures.push_back("1 + L(inf) = 0 with this derivative filter: the loop is ill-posed");
    return;
  }
  // With a delay the roots' high-frequency chain lies at Re s = ln|L(inf)| / tau.
  if (plant.delay_s > 0 && std::abs(l_inf) >= 1.0)
    v.failures.push_back(
        Format("the model has a direct feedthrough (gain %.4g at high frequency) and a delay: the "
               "loop's gain there, |L(inf)| = %.3g, must be below 1 or its high-frequency roots lie "
               "right of the axis whatever the rest of the design",
               g_inf, std::abs(l_inf)));
}

// The gain margins either side of the loop's gain, from every -180 degree
// crossing.
void SplitMargins(const Margins& m, LoopVerdict& v) {
  v.lower_gain_margin = 0;
  v.upper_gain_margin = INFINITY;
  for (double g : m.crossing_margins) {
    if (g < 1.0) v.lower_gain_margin = std::max(v.lower_gain_margin, g);
    if (g >= 1.0) v.upper_gain_margin = std::min(v.upper_gain_margin, g);
  }
}

}  // namespace

bool HasFeedthrough(const model::TransferFunction& plant) { return Degree(plant.num) == Degree(plant.den); }

std::string LoopVerdict::Summary() const {
  std::string out;
  for (const std::string& f : failures) out += (out.empty() ? "" : "; ") + f;
  return out;
}

LoopVerdict CheckLoop(const model::TransferFunction& plant, const Evaluated& e, const LoopRequirements& r) {
  LoopVerdict v;
  CheckWellPosed(plant, e.design.pid, v);
  const double J = e.design.stability_degree;
  const bool stable = std::isfinite(J) && J > 0;
  if (e.design.requested_degree > 0 && !(J >= 0.9 * e.design.requested_degree))
    v.failures.push_back(
        Format("the requested J = %.4g 1/s is not met: the loop's rightmost root with these gains "
               "lies at %.4g 1/s (the triple root's gains do not place it there for this model)",
               e.design.requested_degree, -J));
  if (!stable)
    v.failures.push_back(std::isfinite(J)
                             ? Format("the closed loop is unstable: its rightmost root lies at %+.4g 1/s", -J)
                             : std::string("the closed loop is unstable: its roots run off to the right "
                                           "half plane without bound"));
  else if (!(J > r.min_degree))
    v.failures.push_back(Format("J = %.4g 1/s, not above the required %.4g 1/s", J, r.min_degree));
  SplitMargins(e.margins, v);
  if (stable) {
    v.conditionally_stable = v.lower_gain_margin > 0;
    if (!(v.upper_gain_margin >= r.min_gain_margin))
      v.failures.push_back(Format("gain margin %.3g, below the required %.3g", v.upper_gain_margin, r.min_gain_margin));
    if (!(e.margins.ms <= r.max_ms))
      v.failures.push_back(Format("peak sensitivity Ms %.3g, above the allowed %.3g", e.margins.ms, r.max_ms));
  }
  v.ok = v.failures.empty();
  return v;
}

}  // namespace bead::control
