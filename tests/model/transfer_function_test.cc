#include "libbead/model/transfer_function.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"

namespace bead::model {
namespace {

// 1 / (tau s + 1), a unit step at t = 0: y = 1 - exp(-t / tau), exactly
// at the samples under zero-order hold, on an uneven grid too.
TEST(TransferFunction, FirstOrderStepIsExactOnUnevenSamples) {
  const TransferFunction tf{{1.0}, {0.7, 1.0}, 0.0};
  std::vector<double> t, u;
  for (double x = 0.0; x < 5.0; x += 0.013 + 0.01 * std::sin(7 * x) * std::sin(7 * x)) {
    t.push_back(x);
    u.push_back(1.0);
  }
  const auto y = Simulate(tf, t, u);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(y[k], 1.0 - std::exp(-t[k] / 0.7), 1e-12) << t[k];
}

// A delay shifts the response by exactly that time, even when it is not a
// multiple of the sample time.
TEST(TransferFunction, DelayShiftsTheResponse) {
  TransferFunction tf{{2.0}, {0.5, 1.0}, 0.0123};
  std::vector<double> t, u;
  for (int k = 0; k < 500; ++k) {
    t.push_back(0.01 * k);
    u.push_back(1.0);
  }
  const auto y = Simulate(tf, t, u);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double tt = t[k] - 0.0123;
    EXPECT_NEAR(y[k], tt <= 0 ? 0.0 : 2.0 * (1.0 - std::exp(-tt / 0.5)), 1e-12) << t[k];
  }
}

// Thesis eq. 21: a 1 V step settles at the DC gain, 35.08 RPM; eq. 22's
// biproper form passes its high-frequency gain 9.175 straight through.
TEST(TransferFunction, ThesisModelsSettleAtTheirGains) {
  const TransferFunction v2r = ThesisVoltageToRpm();
  EXPECT_DOUBLE_EQ(v2r.DcGain(), 35.08);
  std::vector<double> t, u;
  for (int k = 0; k <= 60000; ++k) {
    t.push_back(0.01 * k);
    u.push_back(1.0);
  }
  // Slowest pole of 1.523 s^2 + 11.44 s + 1 is at -0.0889 /s (thesis: -0.09): 600 s is 53 time constants.
  EXPECT_NEAR(Simulate(v2r, t, u).back(), 35.08, 1e-6);
  const TransferFunction r2q = ThesisRpmToFlow(0.0);
  const auto q = Simulate(r2q, {0.0, 1e-9}, {1.0, 1.0});
  EXPECT_NEAR(q[0], 9.175, 1e-12);
  EXPECT_NEAR(r2q.DcGain(), 905.3 / 47.52, 1e-12);
}

TEST(TransferFunction, SteppingSystemMatchesBatchSimulation) {
  const TransferFunction tf = ThesisVoltageToRpm();
  TransferFunction no_delay = tf;
  no_delay.delay_s = 0.0;
  DiscreteSystem sys(no_delay, 0.001);
  std::vector<double> t, u, y;
  for (int k = 0; k < 3000; ++k) {
    t.push_back(0.001 * k);
    u.push_back(k < 1000 ? 0.0 : (k < 2000 ? 3.0 : 1.5));
    y.push_back(sys.Step(u.back()));
  }
  const auto batch = Simulate(no_delay, t, u);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(y[k], batch[k], 1e-9);
  sys.Reset(2.0);  // steady state: output equals gain * input
  EXPECT_NEAR(sys.Step(2.0), 2.0 * 35.08, 1e-9);
}

TEST(TransferFunction, RejectsImproperAndEmpty) {
  EXPECT_THROW(ToStateSpace({{1.0, 0.0, 0.0}, {1.0, 1.0}, 0.0}), Error);
  EXPECT_THROW(ToStateSpace({{}, {1.0}, 0.0}), Error);
  EXPECT_THROW(ToStateSpace({{1.0}, {0.0, 1.0}, 0.0}), Error);
}

}  // namespace
}  // namespace bead::model
