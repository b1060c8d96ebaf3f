// The share of the wheel speed's variance that a filter of the model's
// input explains (explain/speed_follows_input.h): a wheel whose speed is a
// first-order lag of the input (a fed-forward wheel) shares nearly all of
// it; a wheel stepped on its own clock next to nothing; a steady wheel
// has nothing to share.
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

}  // namespace
}  // namespace bead::explain
