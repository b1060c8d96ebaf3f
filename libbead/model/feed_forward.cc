#include "libbead/model/feed_forward.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "libbead/core/error.h"

namespace bead::model {
namespace {

TransferFunction WithoutDelay(TransferFunction tf) {
  tf.delay_s = 0.0;
  return tf;
}

}  // namespace

FeedForward::FeedForward(const TransferFunction& voltage_to_rpm, const TransferFunction& rpm_to_flow,
                         const WheelModel& wheel, const FeedForwardOptions& options)
    : dt_(1.0 / options.rate_hz),
      wheel_(wheel),
      options_(options),
      to_rpm_(WithoutDelay(voltage_to_rpm), 1.0 / options.rate_hz),
      to_flow_(WithoutDelay(rpm_to_flow), 1.0 / options.rate_hz) {
  if (!(options.rate_hz > 0) || !(options.target_area_mm2 > 0) || !(wheel.gain_rpm_per_v > 0) || !(wheel.tau_s > 0) ||
      !(wheel.radius_mm > 0))
    throw Error("feed-forward: rate, target area, wheel gain, time constant and radius must be positive");
  // The models' delays, less the wheel's (the wheel is commanded that much
  // ahead), in whole ticks; the chain is linear and time invariant, so
  // where the delay sits does not matter: first the RPM model's, then the rest.
  const double left = std::max(0.0, voltage_to_rpm.delay_s + rpm_to_flow.delay_s - wheel.delay_s);
  const double first = std::min(voltage_to_rpm.delay_s, left);
  command_delay_.assign(static_cast<std::size_t>(std::lround(first / dt_)), 0.0);
  rpm_delay_.assign(static_cast<std::size_t>(std::lround((left - first) / dt_)), 0.0);
  a_ = std::exp(-dt_ / wheel.tau_s);
  to_rpm_dc_ = voltage_to_rpm.DcGain();
  gain_ = (1.0 - options.pole) / (1.0 - a_);
}

void FeedForward::StartAt(double command_v) {
  to_rpm_.Reset(command_v);
  const double rpm = command_v * to_rpm_dc_;
  to_flow_.Reset(rpm);
  std::fill(command_delay_.begin(), command_delay_.end(), command_v);
  std::fill(rpm_delay_.begin(), rpm_delay_.end(), rpm);
}

double FeedForward::Step(double command_v) {
  command_delay_.push_back(command_v);
  const double u1 = command_delay_.front();
  command_delay_.pop_front();
  const double rpm = std::max(0.0, to_rpm_.Step(u1));
  rpm_delay_.push_back(rpm);
  const double u2 = rpm_delay_.front();
  rpm_delay_.pop_front();
  predicted_ = std::max(0.0, to_flow_.Step(u2));
  const double speed = std::max(predicted_ / options_.target_area_mm2, options_.min_speed_mm_s);
  const double wheel_rpm = speed / wheel_.radius_mm * 60.0 / (2.0 * std::numbers::pi);
  const double reference_v = wheel_rpm / wheel_.gain_rpm_per_v;
  if (first_) {  // start as if the reference had always been there
    last_reference_v_ = last_output_v_ = reference_v;
    first_ = false;
  }
  // u[k] = p u[k-1] + K (r[k] - a r[k-1])   (thesis 4.2.1 block)
  double out = options_.pole * last_output_v_ + gain_ * (reference_v - a_ * last_reference_v_);
  last_reference_v_ = reference_v;
  last_output_v_ = out;
  return std::clamp(out, 0.0, options_.max_voltage_v);
}

}  // namespace bead::model
