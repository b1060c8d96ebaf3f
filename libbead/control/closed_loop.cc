#include "libbead/control/closed_loop.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "libbead/control/digital_pid.h"
#include "libbead/control/polynomial.h"

namespace bead::control {
namespace {

using C = std::complex<double>;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Newton on D from `s`; converged roots only (|D| small against its parts).
bool NewtonRoot(const QuasiPolynomial& d, C& s) {
  for (int it = 0; it < 60; ++it) {
    const C f = d(s), df = d.Derivative(s);
    if (std::abs(df) == 0) return false;
    const C step = f / df;
    s -= step;
    if (!std::isfinite(s.real()) || !std::isfinite(s.imag())) return false;
    if (std::abs(step) < 1e-12 * std::max(1.0, std::abs(s))) break;
  }
  const double scale = std::abs(Evaluate(d.p, s)) + std::abs(Evaluate(d.q, s) * std::exp(-d.tau_s * s));
  return std::abs(d(s)) <= 1e-8 * std::max(scale, 1e-300);
}

// The [6/6] Pade approximant of e^(-tau s): N(s) / N(-s), N(s) = sum_k c_k (-tau s)^k.
std::vector<double> PadeNumerator(double tau, int order, bool negate) {
  std::vector<double> c(static_cast<std::size_t>(order + 1));  // ascending
  for (int k = 0; k <= order; ++k) {
    // c_k = (2n - k)! n! / ((2n)! k! (n - k)!)
    double num = 1.0;
    for (int j = 0; j < k; ++j) num *= static_cast<double>(order - j) / static_cast<double>((2 * order - j) * (j + 1));
    c[static_cast<std::size_t>(k)] = num * std::pow(negate ? -tau : tau, k);
  }
  std::reverse(c.begin(), c.end());  // descending
  return c;
}

}  // namespace

C QuasiPolynomial::operator()(C s) const { return Evaluate(p, s) + Evaluate(q, s) * std::exp(-tau_s * s); }

C QuasiPolynomial::Derivative(C s) const {
  const C e = std::exp(-tau_s * s);
  return Evaluate(Differentiate(p), s) + (Evaluate(Differentiate(q), s) - tau_s * Evaluate(q, s)) * e;
}

bool QuasiPolynomial::Neutral() const { return tau_s > 0 && Degree(p) == Degree(q); }

double QuasiPolynomial::NeutralAsymptote() const {
  if (!Neutral()) return NAN;
  return std::log(std::abs(Leading(q) / Leading(p))) / tau_s;
}

QuasiPolynomial Characteristic(const model::TransferFunction& plant, const Pid& pid) {
  const std::vector<double> filter = {pid.tf_s, 1.0};  // 1 + Tf s
  QuasiPolynomial d;
  d.p = Multiply(Multiply({1.0, 0.0}, filter), plant.den);
  const std::vector<double> c =
      Add(Add({pid.kd, 0.0, 0.0}, Multiply({pid.kp, 0.0}, filter)), Multiply({pid.ki}, filter));
  d.q = Multiply(c, plant.num);
  d.tau_s = plant.delay_s;
  if (d.tau_s <= 0) {
    d.p = Add(d.p, d.q);
    d.q = {0.0};
    d.tau_s = 0;
  }
  return d;
}

RightmostRoot FindRightmostRoot(const QuasiPolynomial& d, double max_freq) {
  RightmostRoot out;
  out.real_part = -kInf;
  auto consider = [&](C s) {
    if (s.real() > out.real_part) out.real_part = s.real(), out.root = s;
  };
  if (d.tau_s <= 0) {
    for (const C& r : Roots(Trim(d.p))) consider(r);
    return out;
  }
  if (Degree(d.q) > Degree(d.p)) {  // advanced type
    out.real_part = kInf;
    out.from_chain = true;
    return out;
  }
  // Starts: the Pade roots, then a grid.
  std::vector<C> starts;
  const std::vector<double> pade_num = PadeNumerator(d.tau_s, 6, true), pade_den = PadeNumerator(d.tau_s, 6, false);
  for (const C& r : Roots(Trim(Add(Multiply(d.p, pade_den), Multiply(d.q, pade_num))))) starts.push_back(r);
  if (max_freq <= 0) max_freq = 40.0 / d.tau_s;
  const double re_span = 4.0 / d.tau_s;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 60; ++j) starts.emplace_back(-re_span + 1.25 * re_span * i / 8.0, max_freq * j / 60.0);
  for (C s : starts) {
    if (s.imag() < 0) s = std::conj(s);
    if (NewtonRoot(d, s)) consider(C(s.real(), std::abs(s.imag())));
  }
  if (d.Neutral() && d.NeutralAsymptote() > out.real_part) {
    out.real_part = d.NeutralAsymptote();
    out.from_chain = true;
  }
  return out;
}

std::complex<double> LoopResponse(const model::TransferFunction& plant, const Pid& pid, double w) {
  const C s(0.0, w);
  const C c = pid.kp + pid.ki / s + pid.kd * s / (1.0 + pid.tf_s * s);
  return c * Evaluate(plant.num, s) / Evaluate(plant.den, s) * std::exp(-plant.delay_s * s);
}

Margins ComputeMargins(const model::TransferFunction& plant, const Pid& pid) {
  Margins m;
  m.gain_margin = kInf;
  m.phase_margin_deg = kInf;
  // A log grid over eight decades about the loop's own scales, the phase
  // unwrapped along it.
  double scale = 1e-6;
  for (const C& r : Roots(Trim(plant.den))) scale = std::max(scale, std::abs(r));
  const double lo = 1e-4 * std::min(1.0, scale),
               hi = 1e4 * std::max(scale, plant.delay_s > 0 ? 1 / plant.delay_s : 1.0);
  const int n = 20000;
  double prev_w = 0, prev_mag = 0, prev_phase = 0, phase_offset = 0;
  bool crossed = false;
  for (int k = 0; k <= n; ++k) {
    const double w = lo * std::pow(hi / lo, static_cast<double>(k) / n);
    const C l = LoopResponse(plant, pid, w);
    const double mag = std::abs(l);
    double raw = std::arg(l);
    if (k > 0) {
      while (raw + phase_offset - prev_phase > M_PI) phase_offset -= 2 * M_PI;
      while (raw + phase_offset - prev_phase < -M_PI) phase_offset += 2 * M_PI;
    }
    const double phase = raw + phase_offset;
    m.ms = std::max(m.ms, 1.0 / std::abs(1.0 + l));
    if (k > 0) {
      if (!crossed && prev_mag >= 1.0 && mag < 1.0) {
        const double f = (prev_mag - 1.0) / (prev_mag - mag);
        const double ph = prev_phase + f * (phase - prev_phase);
        m.crossover_rad_s = prev_w + f * (w - prev_w);
        m.phase_margin_deg = 180.0 + ph * 180.0 / M_PI;
        crossed = true;
      }
      // Phase crossings of -180 degrees (mod 360): the smallest margin.
      const double a = (prev_phase + M_PI) / (2 * M_PI), b = (phase + M_PI) / (2 * M_PI);
      if (std::floor(a) != std::floor(b)) {
        const double target = 2 * M_PI * std::max(std::floor(a), std::floor(b)) - M_PI;
        const double f = (target - prev_phase) / (phase - prev_phase);
        const double mg = prev_mag + f * (mag - prev_mag);
        if (mg > 0) {
          m.gain_margin = std::min(m.gain_margin, 1.0 / mg);
          m.crossing_margins.push_back(1.0 / mg);
        }
      }
    }
    prev_w = w, prev_mag = mag, prev_phase = phase;
  }
  return m;
}

namespace {

// The loop stepped at dt: the plant exact (zero-order hold), its delay a
// buffer of whole steps (dt divides it), the PID as digital_pid.h runs it.
StepFigures Simulate(const model::TransferFunction& plant, const Pid& pid, double duration, double dt, double setpoint,
                     double load, double controller_dt) {
  if (dt <= 0) {
    double fastest = 1.0 / std::max(duration, 1e-9);
    for (const C& r : Roots(Trim(plant.den))) fastest = std::max(fastest, std::abs(r));
    if (pid.kd > 0 && pid.kp > 0) fastest = std::max(fastest, pid.kp / pid.kd);
    dt = std::min(duration / 2000.0, 1.0 / (200.0 * fastest) * 20.0);
  }
  std::size_t hold = 1;
  int delay_steps = 0;
  if (controller_dt > 0) {
    hold = static_cast<std::size_t>(std::max(1.0, std::ceil(controller_dt / dt)));
    dt = controller_dt / static_cast<double>(hold);
    delay_steps = static_cast<int>(std::lround(plant.delay_s / dt));
  } else {
    delay_steps = plant.delay_s > 0 ? std::max(1, static_cast<int>(std::ceil(plant.delay_s / dt))) : 0;
    if (delay_steps > 0) dt = plant.delay_s / delay_steps;
  }
  const double pid_dt = dt * static_cast<double>(hold);
  model::TransferFunction undelayed = plant;
  undelayed.delay_s = 0;
  model::DiscreteSystem sys(undelayed, dt);
  sys.Reset(0.0);
  std::deque<double> buffer(static_cast<std::size_t>(delay_steps), 0.0);
  StepFigures f;
  DigitalPid controller(pid, pid_dt);
  controller.Start(0.0, 0.0);  // from rest: the setpoint's step at t = 0 enters the derivative
  double y = 0, u = 0;
  const auto steps = static_cast<std::size_t>(std::ceil(duration / dt));
  for (std::size_t k = 0; k <= steps; ++k) {
    if (k % hold == 0) u = controller.Update(setpoint - y);
    f.t.push_back(static_cast<double>(k) * dt);
    f.y.push_back(y);
    f.u.push_back(u);
    double in = u + load;
    if (delay_steps > 0) {
      buffer.push_back(in);
      in = buffer.front();
      buffer.pop_front();
    }
    y = sys.Step(in);
  }
  return f;
}

}  // namespace

StepFigures SetpointStep(const model::TransferFunction& plant, const Pid& pid, double duration, double dt,
                         double controller_dt) {
  StepFigures f = Simulate(plant, pid, duration, dt, 1.0, 0.0, controller_dt);
  double peak = 0;
  f.settling_s = 0;
  for (std::size_t k = 0; k < f.y.size(); ++k) {
    peak = std::max(peak, f.y[k]);
    f.iae += std::abs(1.0 - f.y[k]) * (k ? f.t[k] - f.t[k - 1] : 0.0);
    if (std::abs(f.y[k] - 1.0) > 0.05) f.settling_s = f.t[k];
  }
  if (std::abs(f.y.back() - 1.0) > 0.05) f.settling_s = kInf;
  f.overshoot_pct = 100.0 * std::max(0.0, peak - 1.0);
  f.peak_deviation = peak;
  return f;
}

StepFigures LoadStep(const model::TransferFunction& plant, const Pid& pid, double duration, double dt,
                     double controller_dt) {
  StepFigures f = Simulate(plant, pid, duration, dt, 0.0, 1.0, controller_dt);
  // The band: 5 % of the load's open-loop effect (the plant's gain).
  const double band = 0.05 * std::abs(plant.DcGain());
  for (std::size_t k = 0; k < f.y.size(); ++k) {
    f.peak_deviation = std::max(f.peak_deviation, std::abs(f.y[k]));
    f.iae += std::abs(f.y[k]) * (k ? f.t[k] - f.t[k - 1] : 0.0);
    if (std::abs(f.y[k]) > band) f.settling_s = f.t[k];
  }
  if (std::abs(f.y.back()) > band) f.settling_s = kInf;
  return f;
}

}  // namespace bead::control
