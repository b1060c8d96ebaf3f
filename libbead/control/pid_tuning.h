// PID designs from a model (control/closed_loop.h for the controller):
//  - max-stability: the PID that maximises the closed loop's degree of
//    stability J (seed 004, Cojuhari et al., section VI; the maximum
//    stability degree criterion of Shubladze, Avtomatika i Telemekhanika
//    1980 no. 1): for each J, the gains that put a triple root of the
//    characteristic function at s = -J (three linear equations), the loop's
//    true rightmost root computed for them, J chosen where that root lies
//    furthest left; where the characteristic function's fourth derivative
//    can vanish at -J too (a fourfold root), that J is tried exactly.
//  - simc: Skogestad, "Simple analytic rules for model reduction and PID
//    controller tuning", J. Process Control 13 (2003) 291-309, eq. (Table
//    1): Kc = tau1 / (k (tauc + theta)), tauI = min(tau1, 4 (tauc + theta)),
//    tauD = tau2, tauc = theta (his tight setting) but at least tau1 / 100, so
//    that a model with almost no delay does not get a gain beyond any
//    actuator's; the model reduced by his half rule.
//  - imc: Rivera, Morari & Skogestad, Ind. Eng. Chem. Process Des. Dev. 25
//    (1986) 252-265, Table I (first order plus delay, delay by a first-order
//    Pade): Kc = (2 tau + theta) / (k (2 lambda + theta)), tauI = tau +
//    theta / 2, tauD = tau theta / (2 tau + theta); lambda = max(0.8 theta,
//    0.2 tau) (their lambda / theta > 0.8 for robustness).
//  - zn: Ziegler & Nichols, Trans. ASME 64 (1942) 759-768, the
//    reaction-curve rule: Kc = 1.2 tau / (k theta), tauI = 2 theta, tauD =
//    theta / 2.
//  - cohen-coon: Cohen & Coon, Trans. ASME 75 (1953) 827-834: Kc = (tau /
//    (k theta)) (4/3 + theta / (4 tau)), tauI = theta (32 + 6 r) / (13 + 8
//    r), tauD = 4 theta / (11 + 2 r), r = theta / tau.
// The rules take a first-order-plus-delay model (k, tau, theta): the
// model's own when it is one; for a model with real poles, Skogestad's
// half rule; otherwise seed 004's step identification of the model's
// simulated step response (model/step_identification.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "libbead/control/closed_loop.h"
#include "libbead/model/transfer_function.h"

namespace bead::control {

struct Fopdt {
  double k = 0, tau_s = 0, theta_s = 0;  // first order plus delay
  // Second order plus delay (SIMC's PID): tau1 >= tau2 (0: none), theta2.
  double tau1_s = 0, tau2_s = 0, theta2_s = 0;
  std::string how;  // "the model's own", "Skogestad's half rule", "seed 004's step identification"
};
Fopdt ReduceToFopdt(const model::TransferFunction& plant);

struct Design {
  bool ok = false;
  std::string method, reason, note;
  Pid pid;
  double stability_degree = 0;  // J: minus the rightmost root's real part, for the gains as printed
  bool unbounded = false;       // max-stability: J grows without bound (the model lacks what limits it)
  Fopdt fopdt;                  // the rules' reduced model
  double requested_degree = 0;  // max-stability at a chosen J: that J (0: maximised)
};

// Methods: "max-stability", "simc", "imc", "zn", "cohen-coon".
std::vector<std::string> Methods();

// `degree`: max-stability at this J instead of the maximum (a model whose J
// is unbounded needs it). Throws bead::Error for an unknown method.
Design DesignPid(const model::TransferFunction& plant, const std::string& method,
                 std::optional<double> degree = std::nullopt);

// A derivative filter Tf = kd / (n kp) on the design (n > 0; kp and kd
// positive, else the design is left ideal), J recomputed for it.
void FilterDerivative(const model::TransferFunction& plant, Design& d, double n);

// The gains that put a triple root of the characteristic function at -J.
Pid TripleRootPid(const model::TransferFunction& plant, double J);

}  // namespace bead::control
