// The share of the wheel speed's variance that a filter of the model's
// input explains (explain/speed_follows_input.h): a wheel whose speed is a
// first-order lag of the input (a fed-forward wheel) shares nearly all of
// it; a wheel stepped on its own clock next to nothing; a steady wheel
// has nothing to share. And the offset-delay correlation the speed's
// changes allow.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libbead/explain/speed_follows_input.h"

namespace bead::explain {
namespace {

// 60 s at 200 Hz: the input a random staircase (a level every 0.5 s), its
// filter basis the input and its first-order lag at 0.3 s; the wheel's
// angle the integral of `speed` (rad/s) at each sample.
template <class Speed>
SeriesData Series(Speed speed) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> level(20.0, 40.0);
  SeriesData d;
  RotatingPart wheel{"wheel", {}};
  double u = 30.0, lag = 30.0, angle = 0.0;
  const double dt = 0.005;
  for (int i = 0; i < 12000; ++i) {
    const double t = i * dt;
    if (i % 100 == 0) u = level(rng);
    lag += dt / 0.3 * (u - lag);
    angle += speed(t, lag) * dt;
    d.t.push_back(t), d.u.push_back(u), d.y.push_back(lag), d.base.push_back(lag);
    wheel.angle_rad.push_back(angle);
  }
  d.dynamics = {d.u, d.y};
  d.parts = {wheel};
  return d;
}

TEST(SpeedShareFromInput, AFedForwardWheelSharesNearlyAllItsChangesAndAWheelSteppedOnItsOwnNone) {
  // Fed forward: the speed follows the lagged input (0.02 rad/s per rpm).
  const double followed = SpeedShareFromInput(Series([](double, double lag) { return 1.0 + 0.02 * lag; }));
  // Stepped on its own: every 10 s, between 1.2 and 1.8 rad/s.
  const double own =
      SpeedShareFromInput(Series([](double t, double) { return static_cast<int>(t / 10.0) % 2 ? 1.8 : 1.2; }));
  std::printf("share: fed forward %.4f, stepped on its own %.4f\n", followed, own);
  EXPECT_GT(followed, 0.99);
  EXPECT_LT(own, 0.1);  // 60 s of a random staircase correlates with six steps by chance only
  EXPECT_TRUE(std::isnan(SpeedShareFromInput(Series([](double, double) { return 1.5; }))));
  SeriesData no_wheel = Series([](double, double) { return 1.5; });
  no_wheel.parts.clear();
  EXPECT_TRUE(std::isnan(SpeedShareFromInput(no_wheel)));
}

// A position error moves the flow the run computes by (Q' - Q v'/v) / v,
// a delay error the model's output by -Q': at a constant speed the two are
// proportional (correlation 1 but for the encoder's quantisation); a wheel
// stepped between 1.2 and 1.8 rad/s every 10 s (its speed's changes
// weighting the flow's slope by 1/v, and each step adding Q v'/v) tells
// them apart.
TEST(OffsetDelayCorrelationFromSpeed, OneAtASteadyWheelAndWellBelowOnAStepped) {
  const double step = 2.0 * M_PI / 10000.0;  // an encoder of 10000 counts per revolution
  SeriesData steady = Series([](double, double) { return 1.5; });
  for (double& a : steady.parts[0].angle_rad) a = step * std::floor(a / step);
  const double at_steady = OffsetDelayCorrelationFromSpeed(steady);
  const double at_stepped = OffsetDelayCorrelationFromSpeed(
      Series([](double t, double) { return static_cast<int>(t / 10.0) % 2 ? 1.8 : 1.2; }));
  std::printf("offset-delay correlation: steady %.4f, stepped %.4f\n", at_steady, at_stepped);
  // confounding.cc's kSteadyWheel (0.99): the steady wheel above it, the
  // stepped one well below (a variance inflation under 10).
  EXPECT_GT(std::abs(at_steady), 0.99);
  EXPECT_LT(std::abs(at_stepped), 0.95);
  SeriesData no_wheel = steady;
  no_wheel.parts.clear();
  EXPECT_TRUE(std::isnan(OffsetDelayCorrelationFromSpeed(no_wheel)));
}

}  // namespace
}  // namespace bead::explain
