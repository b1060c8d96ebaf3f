// Continuous-time transfer functions with an input delay,
//   G(s) = (b0 s^m + ... + bm) / (a0 s^n + ... + an) * exp(-delay s),
// coefficients in descending powers of s, m <= n. Exact discretisation by
// zero-order hold through the matrix exponential, and simulation.
//
// Defaults from the bead characterisation system thesis (large-scale AM extruder dynamics):
//   eq. 21, extruder voltage -> screw RPM: (439 s + 35.08) / (1.523 s^2 + 11.44 s + 1), delay 0.054 s;
//   eq. 22, screw RPM -> flow (mm^3/s, constant wheel speed):
//           (9.175 s^2 + 149.2 s + 905.3) / (s^2 + 12.84 s + 47.52); its delay's digits are lost
//           in the text we have, so callers state one.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

namespace bead::model {

struct TransferFunction {
  std::vector<double> num;  // descending powers of s
  std::vector<double> den;  // descending powers of s, den[0] != 0
  double delay_s = 0.0;

  int poles() const { return static_cast<int>(den.size()) - 1; }
  int zeros() const;
  double DcGain() const;
  // Throws bead::Error when improper, empty or with a zero leading coefficient.
  void Validate() const;
  // The same system with den[0] == 1 (num and den divided by it), the form
  // the responses and filter bases take.
  TransferFunction Monic() const;
};

// The roots of a polynomial in descending powers of s (the eigenvalues of
// its companion matrix); none for a constant.
std::vector<std::complex<double>> PolynomialRoots(const std::vector<double>& coefficients);

// Thesis eq. 21 and eq. 22 (see above).
TransferFunction ThesisVoltageToRpm();
TransferFunction ThesisRpmToFlow(double delay_s);

// x' = A x + B u, y = C x + D u (controllable canonical form).
struct StateSpace {
  Eigen::MatrixXd A;
  Eigen::VectorXd B;
  Eigen::RowVectorXd C;
  double D = 0.0;
};
StateSpace ToStateSpace(const TransferFunction& tf);

// x[k+1] = Ad x[k] + Bd u[k] for u held constant over dt (exact ZOH).
struct DiscreteStateSpace {
  Eigen::MatrixXd Ad;
  Eigen::VectorXd Bd;
  Eigen::RowVectorXd C;
  double D = 0.0;
  double dt = 0.0;
};
DiscreteStateSpace DiscretizeZoh(const StateSpace& ss, double dt);

// Response to u(t) held constant between samples t[k] (which may be
// uneven), from rest, delay included (the input is the held input delayed).
std::vector<double> Simulate(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u);

// Stepping simulator for a fixed dt (the digital twin's inner loop).
class DiscreteSystem {
 public:
  DiscreteSystem(const TransferFunction& tf, double dt);
  // Output for the current (undelayed) input; the delay must be applied by
  // the caller, since it is a property of the input's history.
  double Step(double u);
  void Reset(double steady_input = 0.0);

 private:
  DiscreteStateSpace d_;
  Eigen::VectorXd x_;
};

}  // namespace bead::model
