// A PID controller around a transfer function with an input delay: the
// closed loop's characteristic quasi-polynomial and its rightmost root
// (the degree of stability J is minus its real part), its frequency
// response (gain and phase margins, the peak sensitivity Ms) and its
// responses to a setpoint step and a load step at the plant's input.
//
// Plant G(s) = B(s) / A(s) e^(-tau s); controller (seed 004, eq. 16)
//   C(s) = kp + ki / s + kd s / (1 + Tf s)   (Tf = 0: the ideal PID).
// The loop's characteristic function, cleared of denominators:
//   D(s) = s (1 + Tf s) A(s) + (kd s^2 + kp s (1 + Tf s) + ki (1 + Tf s)) B(s) e^(-tau s).
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "libbead/control/pid_gains.h"
#include "libbead/model/transfer_function.h"

namespace bead::control {

// D(s) = P(s) + Q(s) e^(-tau s), coefficients in descending powers of s.
struct QuasiPolynomial {
  std::vector<double> p, q;
  double tau_s = 0;
  std::complex<double> operator()(std::complex<double> s) const;
  std::complex<double> Derivative(std::complex<double> s) const;
  // Neutral type: P and Q of equal degree (roots chain toward a vertical
  // line Re s = ln|q0 / p0| / tau at high frequency).
  bool Neutral() const;
  double NeutralAsymptote() const;  // the chain's line (NaN when retarded or tau = 0)
};

QuasiPolynomial Characteristic(const model::TransferFunction& plant, const Pid& pid);

// With a delay and Q of higher degree than P (an ideal derivative on a
// plant with a direct feedthrough) the quasi-polynomial is of advanced
// type: its roots run off to the right without bound, real_part = +inf.
struct RightmostRoot {
  std::complex<double> root;
  double real_part = 0;     // max Re over the roots (for a neutral loop, at least the chain's line)
  bool from_chain = false;  // a neutral loop's high-frequency chain sets it
};

// Exact for tau = 0 (polynomial roots). With a delay: Newton on D itself
// from the roots of D with e^(-tau s) replaced by its [6/6] Pade
// approximant and from a grid up to `max_freq_rad_s` (0: 40 / tau); the
// answer is a root of D, not of the approximation.
RightmostRoot FindRightmostRoot(const QuasiPolynomial& d, double max_freq_rad_s = 0);

// The loop L(jw) = C(jw) G(jw).
std::complex<double> LoopResponse(const model::TransferFunction& plant, const Pid& pid, double w);

struct Margins {
  double gain_margin = 0;       // 1 / |L| where its phase crosses -180 degrees (inf: never)
  double phase_margin_deg = 0;  // 180 + phase of L where |L| = 1 (the first crossing)
  double crossover_rad_s = 0;   // where |L| = 1
  double ms = 0;                // max |1 / (1 + L)|
  // 1 / |L| at every -180 degree crossing: below 1 where the loop's gain
  // is above the critical one there (a conditionally stable loop has such
  // a crossing and is stable all the same).
  std::vector<double> crossing_margins;
};
Margins ComputeMargins(const model::TransferFunction& plant, const Pid& pid);

struct StepFigures {
  double overshoot_pct = 0;     // peak beyond the final value, % of the step
  double settling_s = 0;        // last time outside +-5 % of the step (seed 004's band); inf: never inside
  double iae = 0;               // integral of |error|
  double peak_deviation = 0;    // load step: the output's largest excursion
  std::vector<double> t, y, u;  // the response (output and controller output)
};
// A unit setpoint step (setpoint weight 1 on every term, the derivative
// on the error, as eq. 16) and a unit load step at the plant's input,
// simulated with the delay exact (a buffer of whole steps at dt; dt: 0 =
// the loop's fastest time scale / 200) for `duration_s`. With
// `controller_dt` > 0 the PID is digital: it samples the output and
// updates its output every controller_dt, held in between (dt then divides
// it, and the delay is rounded to whole steps of dt).
StepFigures SetpointStep(const model::TransferFunction& plant, const Pid& pid, double duration_s, double dt = 0,
                         double controller_dt = 0);
StepFigures LoadStep(const model::TransferFunction& plant, const Pid& pid, double duration_s, double dt = 0,
                     double controller_dt = 0);

}  // namespace bead::control
