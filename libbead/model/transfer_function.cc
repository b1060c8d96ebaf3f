#include "libbead/model/transfer_function.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <map>

#include "libbead/core/error.h"

namespace bead::model {

int TransferFunction::zeros() const {
  // Leading zero coefficients of the numerator do not count.
  std::size_t i = 0;
  while (i + 1 < num.size() && num[i] == 0.0) ++i;
  return static_cast<int>(num.size() - i) - 1;
}

double TransferFunction::DcGain() const { return num.back() / den.back(); }

void TransferFunction::Validate() const {
  if (den.empty() || num.empty()) throw Error("transfer function: numerator and denominator must not be empty");
  if (den[0] == 0.0) throw Error("transfer function: leading denominator coefficient is zero");
  if (zeros() > poles()) throw Error("transfer function: more zeros than poles (improper)");
  if (!(delay_s >= 0.0)) throw Error("transfer function: delay must be >= 0 s");
}

std::vector<std::complex<double>> PolynomialRoots(const std::vector<double>& a) {
  const int n = static_cast<int>(a.size()) - 1;
  std::vector<std::complex<double>> out;
  if (n < 1) return out;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) companion(0, k) = -a[static_cast<std::size_t>(k + 1)] / a[0];
  for (int k = 1; k < n; ++k) companion(k, k - 1) = 1.0;
  const Eigen::VectorXcd r = companion.eigenvalues();
  for (int k = 0; k < n; ++k) out.push_back(r(k));
  return out;
}

TransferFunction TransferFunction::Monic() const {
  TransferFunction m = *this;
  const double lead = den.at(0);
  for (double& c : m.num) c /= lead;
  for (double& c : m.den) c /= lead;
  return m;
}

TransferFunction ThesisVoltageToRpm() { return {{439.0, 35.08}, {1.523, 11.44, 1.0}, 0.054}; }

TransferFunction ThesisRpmToFlow(double delay_s) { return {{9.175, 149.2, 905.3}, {1.0, 12.84, 47.52}, delay_s}; }

StateSpace ToStateSpace(const TransferFunction& tf) {
  tf.Validate();
  const int n = tf.poles();
  const TransferFunction m = tf.Monic();
  const std::vector<double>& a = m.den;
  std::vector<double> b(static_cast<std::size_t>(n + 1), 0.0);
  // Numerator padded to degree n.
  const std::size_t pad = static_cast<std::size_t>(n + 1) - m.num.size();
  for (std::size_t i = 0; i < m.num.size(); ++i) b[pad + i] = m.num[i];
  StateSpace ss;
  ss.D = b[0];
  ss.A = Eigen::MatrixXd::Zero(n, n);
  ss.B = Eigen::VectorXd::Zero(n);
  ss.C = Eigen::RowVectorXd::Zero(n);
  if (n == 0) return ss;
  // Controllable canonical form: states x1 = y-ish derivatives, last row the characteristic polynomial.
  for (int i = 0; i + 1 < n; ++i) ss.A(i, i + 1) = 1.0;
  for (int j = 0; j < n; ++j) ss.A(n - 1, j) = -a[static_cast<std::size_t>(n - j)];
  ss.B(n - 1) = 1.0;
  for (int j = 0; j < n; ++j) ss.C(j) = b[static_cast<std::size_t>(n - j)] - a[static_cast<std::size_t>(n - j)] * b[0];
  return ss;
}

DiscreteStateSpace DiscretizeZoh(const StateSpace& ss, double dt) {
  const int n = static_cast<int>(ss.A.rows());
  DiscreteStateSpace d;
  d.C = ss.C;
  d.D = ss.D;
  d.dt = dt;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n + 1, n + 1);
  m.topLeftCorner(n, n) = ss.A * dt;
  m.topRightCorner(n, 1) = ss.B * dt;
  const Eigen::MatrixXd e = m.exp();
  d.Ad = e.topLeftCorner(n, n);
  d.Bd = e.topRightCorner(n, 1);
  return d;
}

std::vector<double> Simulate(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u) {
  if (t.size() != u.size()) throw Error("Simulate: time and input lengths differ");
  const StateSpace ss = ToStateSpace(tf);
  const int n = static_cast<int>(ss.A.rows());
  std::vector<double> y(t.size(), 0.0);
  if (t.empty()) return y;
  // Held input u(t) = u[k] on [t[k], t[k+1]); the delayed input switches
  // to u[j] at s[j] = t[j] + delay, compared as such (subtracting the delay
  // from a time that is itself t[j] + delay can round below t[j]).
  std::vector<double> s(t.size());
  for (std::size_t j = 0; j < t.size(); ++j) s[j] = t[j] + tf.delay_s;
  auto held = [&](double time) {
    const auto it = std::upper_bound(s.begin(), s.end(), time);
    return it == s.begin() ? 0.0 : u[static_cast<std::size_t>(it - s.begin()) - 1];
  };
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::map<double, DiscreteStateSpace> cache;  // by the exact step, for even sampling
  auto discrete = [&](double dt) -> const DiscreteStateSpace& {
    auto it = cache.find(dt);
    if (it == cache.end()) it = cache.emplace(dt, DiscretizeZoh(ss, dt)).first;
    return it->second;
  };
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double uk = held(t[k]);
    y[k] = (n ? (ss.C * x)(0) : 0.0) + ss.D * uk;
    if (k + 1 == t.size()) break;
    // Integrate to t[k+1], splitting where the delayed input switches.
    double from = t[k];
    const double to = t[k + 1];
    while (from < to) {
      const double u_now = held(from);
      // Next switch of the delayed input after `from`.
      const auto it = std::upper_bound(s.begin(), s.end(), from);
      const double until = it == s.end() ? to : std::min(*it, to);
      if (n) {
        const DiscreteStateSpace& d = discrete(until - from);
        x = d.Ad * x + d.Bd * u_now;
      }
      from = until;
    }
  }
  return y;
}

DiscreteSystem::DiscreteSystem(const TransferFunction& tf, double dt) : d_(DiscretizeZoh(ToStateSpace(tf), dt)) {
  x_ = Eigen::VectorXd::Zero(d_.Ad.rows());
}

double DiscreteSystem::Step(double u) {
  const double y = (x_.size() ? (d_.C * x_)(0) : 0.0) + d_.D * u;
  if (x_.size()) x_ = d_.Ad * x_ + d_.Bd * u;
  return y;
}

void DiscreteSystem::Reset(double steady_input) {
  const int n = static_cast<int>(d_.Ad.rows());
  if (n == 0) return;
  // Steady state: x = Ad x + Bd u  =>  (I - Ad) x = Bd u.
  x_ = (Eigen::MatrixXd::Identity(n, n) - d_.Ad).fullPivLu().solve(d_.Bd * steady_input);
}

}  // namespace bead::model
