#include "libbead/control/pid_tuning.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "libbead/control/polynomial.h"
#include "libbead/core/error.h"
#include "libbead/model/step_identification.h"

namespace bead::control {
namespace {

double Binomial(int n, int k) {
  double b = 1;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

// Row m of the linear system D^(m)(s) = 0 in (kp, ki, kd) at real s, and
// its right-hand side -P^(m)(s): D = s A(s) + (kd s^2 + kp s + ki) B(s) e^(-tau s).
void Row(const model::TransferFunction& plant, double s, int m, double* coef, double& rhs) {
  std::vector<double> p = Multiply({1.0, 0.0}, plant.den);
  for (int k = 0; k < m; ++k) p = Differentiate(p);
  rhs = -Evaluate(p, s).real();
  const double e = std::exp(-plant.delay_s * s);
  // R^(k)(s) = e^(-tau s) sum_i C(k, i) B^(i)(s) (-tau)^(k - i)
  auto r = [&](int k) {
    double v = 0;
    std::vector<double> b = plant.num;
    for (int i = 0; i <= k; ++i) {
      v += Binomial(k, i) * Evaluate(b, s).real() * std::pow(-plant.delay_s, k - i);
      b = Differentiate(b);
    }
    return v * e;
  };
  // g^(j) in (kp, ki, kd): j = 0: (s, 1, s^2); 1: (1, 0, 2 s); 2: (0, 0, 2).
  const double g[3][3] = {{s, 1.0, s * s}, {1.0, 0.0, 2 * s}, {0.0, 0.0, 2.0}};
  coef[0] = coef[1] = coef[2] = 0;
  for (int j = 0; j <= std::min(m, 2); ++j) {
    const double w = Binomial(m, j) * r(m - j);
    for (int c = 0; c < 3; ++c) coef[c] += w * g[j][c];
  }
}

// The fourfold-root condition: the 4 x 4 system's determinant at -J.
double FourfoldDeterminant(const model::TransferFunction& plant, double J) {
  Eigen::Matrix4d a;
  for (int m = 0; m < 4; ++m) {
    double c[3], rhs;
    Row(plant, -J, m, c, rhs);
    a.row(m) << c[0], c[1], c[2], rhs;
  }
  return a.determinant();
}

double RoundSignificant(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return std::strtod(buf, nullptr);
}

double StabilityDegree(const model::TransferFunction& plant, const Pid& pid) {
  return -FindRightmostRoot(Characteristic(plant, pid)).real_part;
}

// The plant's own scale: its fastest pole and its delay's inverse.
double Scale(const model::TransferFunction& plant) {
  double s = plant.delay_s > 0 ? 1.0 / plant.delay_s : 0.0;
  for (const auto& r : Roots(plant.den)) s = std::max(s, std::abs(r));
  return s > 0 ? s : 1.0;
}

Design MaxStability(const model::TransferFunction& plant, std::optional<double> fixed) {
  Design d;
  d.method = "max-stability";
  if (fixed) {
    if (!(*fixed > 0)) throw Error("the stability degree J must be > 0");
    d.pid = TripleRootPid(plant, *fixed);
    d.ok = true;
    d.requested_degree = *fixed;
    d.note = "J chosen: a triple root of the closed loop at -J";
    return d;
  }
  const double scale = Scale(plant), lo = 1e-3 * scale, hi = 4 * scale;
  auto sigma = [&](double J) {
    const Pid p = TripleRootPid(plant, J);
    return std::isfinite(p.kp + p.ki + p.kd) ? StabilityDegree(plant, p) : -INFINITY;
  };
  const int n = 160;
  double best_j = lo, best = -INFINITY, prev_det = FourfoldDeterminant(plant, lo), prev_j = lo;
  std::vector<double> fourfold;
  for (int k = 0; k <= n; ++k) {
    const double J = lo * std::pow(hi / lo, static_cast<double>(k) / n);
    const double s = sigma(J);
    if (s > best) best = s, best_j = J;
    const double det = FourfoldDeterminant(plant, J);
    if (k > 0 && std::isfinite(det) && std::isfinite(prev_det) && (det > 0) != (prev_det > 0)) {
      double a = prev_j, b = J, fa = prev_det;
      for (int it = 0; it < 200 && b - a > 1e-15 * b; ++it) {
        const double m = 0.5 * (a + b), fm = FourfoldDeterminant(plant, m);
        ((fm > 0) == (fa > 0) ? a : b) = m;
        if ((fm > 0) == (fa > 0)) fa = fm;
      }
      fourfold.push_back(0.5 * (a + b));
    }
    prev_det = det, prev_j = J;
  }
  if (best_j >= hi * 0.999 && best > 0.95 * hi) {
    d.unbounded = true;
    d.reason =
        "the degree of stability grows without bound with the derivative gain for this model (its order and delay "
        "do not limit it): choose J (--degree), or identify the lag that limits it";
    return d;
  }
  // Golden section about the best grid point, then the fourfold roots.
  const double step = std::pow(hi / lo, 1.0 / n);
  double a = best_j / step, b = best_j * step;
  const double phi = (std::sqrt(5.0) - 1) / 2;
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a), f1 = sigma(x1), f2 = sigma(x2);
  for (int it = 0; it < 50; ++it) {
    if (f1 > f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - phi * (b - a), f1 = sigma(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + phi * (b - a), f2 = sigma(x2);
    }
  }
  if (const double s = sigma(0.5 * (a + b)); s > best) best = s, best_j = 0.5 * (a + b);
  for (double J : fourfold)
    if (const double s = sigma(J); s >= best - 1e-9 * std::abs(best)) best = s, best_j = J;
  if (!(best > 0)) {
    d.reason = "no PID puts every closed-loop root in the left half plane for this model";
    if (plant.delay_s > 0 && Degree(plant.num) == Degree(plant.den))
      d.reason +=
          " (it has a direct feedthrough and a delay: with the ideal derivative this design places, the "
          "loop is of advanced type and unstable whatever the gains; a rule with --filter may do)";
    return d;
  }
  d.pid = TripleRootPid(plant, best_j);
  d.ok = true;
  d.note = "J maximised: the closed loop's rightmost root as far left as a PID can put it";
  return d;
}

// A parallel PID from the series (interacting) form Kc (1 + 1/(tauI s)) (1 + tauD s).
Pid FromSeries(double kc, double ti, double td) {
  const double f = 1 + td / ti;
  return {kc * f, kc * f / (ti + td), kc * f * ti * td / (ti + td), 0.0};
}

// A parallel PID from the ideal form Kc (1 + 1/(tauI s) + tauD s).
Pid FromIdeal(double kc, double ti, double td) { return {kc, kc / ti, kc * td, 0.0}; }

}  // namespace

std::vector<std::string> Methods() { return {"max-stability", "simc", "imc", "zn", "cohen-coon"}; }

Pid TripleRootPid(const model::TransferFunction& plant, double J) {
  Eigen::Matrix3d a;
  Eigen::Vector3d b;
  for (int m = 0; m < 3; ++m) {
    double c[3], rhs;
    Row(plant, -J, m, c, rhs);
    a.row(m) << c[0], c[1], c[2];
    b(m) = rhs;
  }
  const Eigen::Vector3d x = a.fullPivLu().solve(b);
  return {x(0), x(1), x(2), 0.0};
}

void FilterDerivative(const model::TransferFunction& plant, Design& d, double n) {
  if (!d.ok || !(n > 0) || !(d.pid.kd > 0) || !(d.pid.kp > 0)) return;
  d.pid.tf_s = d.pid.kd / (n * d.pid.kp);
  d.stability_degree = StabilityDegree(plant, d.pid);
}

Fopdt ReduceToFopdt(const model::TransferFunction& plant) {
  Fopdt f;
  f.k = plant.DcGain();
  std::vector<double> T;
  bool real = Degree(plant.num) == 0;
  for (const auto& r : Roots(plant.den)) {
    if (std::abs(r.imag()) > 1e-9 * std::abs(r) || !(r.real() < 0)) real = false;
    T.push_back(-1.0 / r.real());
  }
  if (real && !T.empty()) {
    std::sort(T.rbegin(), T.rend());
    auto sum_from = [&](std::size_t i) {
      double s = 0;
      for (; i < T.size(); ++i) s += T[i];
      return s;
    };
    const double t2 = T.size() > 1 ? T[1] : 0.0, t3 = T.size() > 2 ? T[2] : 0.0;
    f.tau_s = T[0] + t2 / 2;
    f.theta_s = plant.delay_s + t2 / 2 + sum_from(2);
    f.tau1_s = T[0];
    f.tau2_s = t2 + t3 / 2;
    f.theta2_s = plant.delay_s + t3 / 2 + sum_from(3);
    f.how = T.size() == 1 ? "the model's own" : "Skogestad's half rule";
    return f;
  }
  // The model's own step response, identified as seed 004 does.
  double slow = INFINITY;
  for (const auto& r : Roots(plant.den)) slow = std::min(slow, std::abs(r.real()));
  const double horizon = 10.0 / (std::isfinite(slow) && slow > 0 ? slow : 1.0) + plant.delay_s;
  std::vector<double> t, u;
  for (int i = 0; i <= 20000; ++i) t.push_back(horizon * i / 20000.0), u.push_back(i >= 100 ? 1.0 : 0.0);
  const auto y = model::Simulate(plant, t, u);
  const model::StepModel m = model::IdentifyFromStep(t, y, t[100], 1.0);
  f.k = m.k, f.tau_s = m.T_s, f.theta_s = std::max(m.tau_s, 0.0);
  f.how = "seed 004's step identification";
  return f;
}

Design DesignPid(const model::TransferFunction& plant, const std::string& method, std::optional<double> degree) {
  plant.Validate();
  Design d;
  if (method == "max-stability") {
    d = MaxStability(plant, degree);
  } else {
    d.method = method;
    const Fopdt f = ReduceToFopdt(plant);
    d.fopdt = f;
    if (!(f.k != 0) || !(f.tau_s > 0)) {
      d.reason = "the model reduces to no first-order-plus-delay form (gain " + std::to_string(f.k) + ")";
      return d;
    }
    const double k = f.k, tau = f.tau_s, theta = f.theta_s;
    if (method == "simc") {
      const bool second = f.tau2_s > 0;
      const double th = second ? f.theta2_s : theta, t1 = second ? f.tau1_s : tau, tauc = std::max(th, 0.01 * t1);
      const double kc = t1 / (k * (tauc + th)), ti = std::min(t1, 4 * (tauc + th));
      d.pid = FromSeries(kc, ti, second ? f.tau2_s : 0.0);
      d.note = "tauc = theta (Skogestad's tight setting), at least tau1 / 100";
    } else if (method == "imc") {
      const double lambda = std::max(0.8 * theta, 0.2 * tau);
      d.pid =
          FromIdeal((2 * tau + theta) / (k * (2 * lambda + theta)), tau + theta / 2, tau * theta / (2 * tau + theta));
      char buf[80];
      std::snprintf(buf, sizeof buf, "lambda = %.4g s", lambda);
      d.note = buf;
    } else if (method == "zn" || method == "cohen-coon") {
      if (!(theta > 0)) {
        d.reason = "a reaction-curve rule needs a delay (the model's reduction has none)";
        return d;
      }
      if (method == "zn") {
        d.pid = FromIdeal(1.2 * tau / (k * theta), 2 * theta, theta / 2);
      } else {
        const double r = theta / tau;
        d.pid = FromIdeal(tau / (k * theta) * (4.0 / 3 + r / 4), theta * (32 + 6 * r) / (13 + 8 * r),
                          4 * theta / (11 + 2 * r));
      }
    } else {
      std::string all;
      for (const auto& m : Methods()) all += (all.empty() ? "" : ", ") + m;
      throw Error("--method must be one of " + all + ", got '" + method + "'");
    }
    d.ok = true;
  }
  if (!d.ok) return d;
  d.pid.kp = RoundSignificant(d.pid.kp), d.pid.ki = RoundSignificant(d.pid.ki), d.pid.kd = RoundSignificant(d.pid.kd);
  d.stability_degree = StabilityDegree(plant, d.pid);
  return d;
}

}  // namespace bead::control
