#include "libbead/control/feed_forward_plan.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "libbead/core/error.h"
#include "libbead/model/predict.h"

namespace bead::control {
namespace {

double RmsRel(const std::vector<double>& area, double target, std::size_t from) {
  double s = 0;
  std::size_t n = 0;
  for (std::size_t i = from; i < area.size(); ++i)
    if (std::isfinite(area[i])) s += (area[i] / target - 1) * (area[i] / target - 1), ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : NAN;
}

}  // namespace

WheelPlan PlanWheel(const std::vector<double>& t, const std::vector<double>& v, const model::TransferFunction& v2r,
                    const model::TransferFunction& r2q, const model::WheelModel& wheel,
                    const model::FeedForwardOptions& o) {
  if (t.size() < 2 || t.size() != v.size()) throw Error("a plan needs at least 2 samples of time and command");
  model::FeedForward ff(v2r, r2q, wheel, o);
  ff.StartAt(v.front());
  WheelPlan p;
  const double dt = 1.0 / o.rate_hz;
  std::size_t j = 0;
  for (double tick = t.front(); tick <= t.back() + 1e-9 * dt; tick += dt) {
    while (j + 1 < t.size() && t[j + 1] <= tick) ++j;
    p.t_s.push_back(tick);
    p.extruder_cmd_v.push_back(v[j]);
    p.wheel_cmd_v.push_back(ff.Step(v[j]));
  }
  // What the models predict: the flow from the command, the wheel's speed
  // from its command (first order and delay, thesis 3.3.3), the area.
  const std::vector<double> rpm = model::Predict(v2r, 0.0, p.t_s, p.extruder_cmd_v, {});
  p.flow_mm3_s = model::Predict(r2q, 0.0, p.t_s, rpm, {});
  const model::TransferFunction wheel_tf{{wheel.gain_rpm_per_v}, {wheel.tau_s, 1.0}, wheel.delay_s};
  const std::vector<double> wheel_rpm = model::Predict(wheel_tf, 0.0, p.t_s, p.wheel_cmd_v, {});
  double mean_flow = 0;
  for (std::size_t i = 0; i < p.t_s.size(); ++i) {
    p.speed_mm_s.push_back(wheel_rpm[i] * 2 * std::numbers::pi / 60.0 * wheel.radius_mm);
    p.area_mm2.push_back(p.speed_mm_s[i] > 0 ? p.flow_mm3_s[i] / p.speed_mm_s[i] : NAN);
    mean_flow += p.flow_mm3_s[i] / static_cast<double>(p.t_s.size());
  }
  std::vector<double> constant(p.flow_mm3_s.size());
  const double speed = mean_flow / o.target_area_mm2;
  for (std::size_t i = 0; i < constant.size(); ++i) constant[i] = p.flow_mm3_s[i] / speed;
  p.rms_rel_planned = RmsRel(p.area_mm2, o.target_area_mm2, 0);
  p.rms_rel_constant = RmsRel(constant, o.target_area_mm2, 0);
  return p;
}

}  // namespace bead::control
