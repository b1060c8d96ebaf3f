// Stretches where the process started (a weld's arc struck, the extruder's
// material arriving): the state is at rest there, so the start-up rise is a
// step response the identification uses, not an unknown to estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"
#include "tests/support/random_steps.h"

namespace bead::model {
namespace {

// y' = (K u(t - Td) - y) / T, at rest at `start` (the wire fed before it
// arriving through the delay), stepped exactly on a 1 ms
// grid (the input and its 0.1 s delay are constant over each step: the
// switches fall on the grid). Written here, not with the library's walk.
std::vector<double> FirstOrderFromRest(double K, double T, double Td, const std::vector<double>& t,
                                       const std::vector<double>& u, double start, double stop) {
  std::vector<double> y(t.size(), 0.0);
  const double h = 1e-3, decay = std::exp(-h / T);
  const double dt = t[1] - t[0];
  double x = 0.0, tau = start;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < start - 1e-9 || t[i] >= stop - 1e-9) continue;
    while (tau < t[i] - 1e-9) {
      const long j = std::lround(std::floor((tau + 0.5 * h - Td) / dt));  // the delayed input's sample
      const double v = j < 0 ? u.front() : u[static_cast<std::size_t>(j)];
      x = decay * x + (1 - decay) * K * v;
      tau += h;
    }
    y[i] = x;
  }
  return y;
}

// The arc off (the output at zero, the wire still fed) at the start and
// again at 30-34 s; after each the bead grows from nothing. Both stretches
// are found to start from rest, and the fit recovers gain, time constant
// and delay from data whose start-ups carry most of the transient.
TEST(ProcessStart, ArcStrikesAreStepResponsesFromRest) {
  const double K = 1.2, T = 0.5, Td = 0.1;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto [t, u] = test::RandomSteps(rng, 2.0, 6.0, 3000, 150, 0.02);
  const std::vector<double> a = FirstOrderFromRest(K, T, Td, t, u, 5.0, 30.0);
  const std::vector<double> b = FirstOrderFromRest(K, T, Td, t, u, 34.0, 60.0);
  std::vector<double> y(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool on = (t[i] > 5.0 - 1e-9 && t[i] < 30.0 - 1e-9) || t[i] > 34.0 - 1e-9;
    y[i] = on ? a[i] + b[i] + noise(rng) : 0.0;
  }
  const ProcessOn on = FindProcessOn(t, u, y);
  ASSERT_EQ(on.segments.size(), 2u) << DescribeExclusions(on.excluded);
  EXPECT_TRUE(on.segments[0].process_starts);
  EXPECT_TRUE(on.segments[1].process_starts);
  // At rest at the last zero sample: the strike.
  EXPECT_NEAR(t[on.segments[0].begin], 5.0, 1e-9);
  EXPECT_NEAR(t[on.segments[1].begin], 34.0, 1e-9);
  IdentifyOptions o;
  o.poles = 1;
  o.zeros = 0;
  const IdentifiedModel m = IdentifyTransferFunction(t, u, y, o, on.segments);
  ASSERT_TRUE(m.ok) << m.reason;
  // Noise 0.02 on 2700 samples moves the gain by ~1e-4; the tolerances are
  // the delay's sample (0.02 s) and its share of the time constant.
  EXPECT_NEAR(m.tf.DcGain(), K, 0.01);
  EXPECT_NEAR(m.process.Tp_s[0], T, 0.02);
  EXPECT_NEAR(m.tf.delay_s, Td, 0.021);
  EXPECT_NEAR(m.offset, 0.0, 0.05);
  // The model's output at each start is the rest the data show, and the
  // rise is fitted: the start-up samples are in the fit.
  for (const Segment& s : on.segments) {
    EXPECT_NEAR(m.prediction[s.begin], 0.0, 0.05);
    EXPECT_NEAR(m.prediction[s.begin + 10], y[s.begin + 10], 4 * 0.02 + 0.05);
  }
  EXPECT_EQ(m.fitted_samples, on.fitted_samples);
}

// The output read zero while the process ran on (it comes back at its
// level, not from nothing): that stretch's state is its own, estimated.
TEST(ProcessStart, OutputBackAtItsLevelWasRunningAllAlong) {
  std::vector<double> t, u, y;
  for (int i = 0; i < 1000; ++i) {
    t.push_back(0.02 * i);
    u.push_back(3.0);
    y.push_back(t.back() >= 8.0 && t.back() < 9.0 ? 0.0 : 3.6);
  }
  const ProcessOn on = FindProcessOn(t, u, y);
  ASSERT_EQ(on.segments.size(), 2u);
  EXPECT_FALSE(on.segments[0].process_starts);  // the record's start
  EXPECT_FALSE(on.segments[1].process_starts);
}

}  // namespace
}  // namespace bead::model
