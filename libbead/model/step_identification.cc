#include "libbead/model/step_identification.h"

#include <cmath>

namespace bead::model {

StepModel IdentifyFromStep(const std::vector<double>& t, const std::vector<double>& y, double t_step, double step,
                           double final_fraction) {
  StepModel m;
  const std::size_t n = t.size();
  if (n < 10 || y.size() != n || step == 0.0) {
    m.reason = "need at least 10 samples and a non-zero step";
    return m;
  }
  // Initial value: the mean before the step (or the first sample).
  double y0 = 0;
  std::size_t before = 0;
  for (std::size_t i = 0; i < n && t[i] <= t_step; ++i) y0 += y[i], ++before;
  y0 = before ? y0 / before : y[0];
  const std::size_t tail = std::max<std::size_t>(1, static_cast<std::size_t>(final_fraction * n));
  double yf = 0;
  for (std::size_t i = n - tail; i < n; ++i) yf += y[i];
  yf /= tail;
  const double dy = yf - y0;
  m.k = dy / step;
  // Noise level before the step: the output has "left" once it exceeds it.
  double noise = 0;
  for (std::size_t i = 0; i < before; ++i) noise = std::max(noise, std::abs(y[i] - y0));
  const double sign = dy > 0 ? 1.0 : -1.0;
  std::size_t first = n;
  for (std::size_t i = 0; i < n; ++i)
    if (t[i] > t_step && sign * (y[i] - y0) > noise) {
      first = i;
      break;
    }
  if (first + 1 >= n) {
    m.reason = "the output never leaves its initial value";
    return m;
  }
  // Extend the line through the first two departed samples back to y0.
  const double slope = (y[first + 1] - y[first]) / (t[first + 1] - t[first]);
  double tau_abs = t[first] - (y[first] - y0) / slope;
  tau_abs = std::max(tau_abs, t_step);
  m.tau_s = tau_abs - t_step;
  // 0.632 k: interpolated crossing.
  const double level = y0 + 0.632 * dy;
  for (std::size_t i = first; i < n; ++i) {
    if (sign * (y[i] - level) >= 0) {
      const double f = (level - y[i - 1]) / (y[i] - y[i - 1]);
      const double t2 = t[i - 1] + f * (t[i] - t[i - 1]);
      m.T_s = t2 - tau_abs;
      break;
    }
  }
  if (!(m.T_s > 0)) {
    m.reason = "the output never reaches 0.632 of its change";
    return m;
  }
  m.T2_s = 0.64 * m.T_s;  // eq. 7
  m.T1_s = 0.32 * m.T_s;
  m.first_order = {{m.k}, {m.T_s, 1.0}, m.tau_s};
  m.second_order = {{m.k}, {m.T1_s * m.T2_s, m.T1_s + m.T2_s, 1.0}, m.tau_s};
  m.ok = true;
  return m;
}

}  // namespace bead::model
