// Models from one step response, by the graph-analytic method of
// Cojuhari et al., "Synthesis of the PID Algorithm for Control the Thermal Regime in the 3D Printer" (section IV):
//   k   = (y_final - y_initial) / (input step)                        (eq. 1-2)
//   tau = where the output leaves its initial value (eq. 4: "null");
//         found by extending the first rising samples back to it
//   T   = t(0.632 k) - tau                                            (eq. 3, 5, 6)
//   first order plus delay:  k e^(-tau s) / (T s + 1)                  (eq. 9)
//   second order:            T2 = 0.64 T, T1 = 0.32 T                  (eq. 7)
//                            k e^(-tau s) / ((T2 s + 1) (T1 s + 1))    (eq. 9, 15)
#pragma once

#include <string>
#include <vector>

#include "libbead/model/transfer_function.h"

namespace bead::model {

struct StepModel {
  bool ok = false;
  std::string reason;
  double k = 0, tau_s = 0, T_s = 0, T1_s = 0, T2_s = 0;
  TransferFunction first_order;   // k e^(-tau s) / (T s + 1)
  TransferFunction second_order;  // k e^(-tau s) / (0.2048 T^2 s^2 + 0.96 T s + 1)
};

// t, y: the response; the step of size `step` is applied at t_step.
// The final value is the mean of the last `final_fraction` of the samples.
StepModel IdentifyFromStep(const std::vector<double>& t, const std::vector<double>& y, double t_step, double step,
                           double final_fraction = 0.05);

}  // namespace bead::model
