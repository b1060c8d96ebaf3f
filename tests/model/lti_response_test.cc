// The state walk of identification (grid-composed steps on uneven sampling,
// a delay switching inside steps) against the plain exact simulation,
// which takes a matrix exponential for every piece (this test found the
// latter switching late where t[j] + delay - delay rounded below t[j]): the same output to
// rounding, for a biproper model with complex poles and a sub-sample
// delay, sampled with +-40 % jitter (the composed steps' truncation is
// below 1e-12 of the state; 1e-9 of the output's scale allows for the
// sums over 6000 steps).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libbead/model/identify.h"
#include "libbead/model/lti_response.h"

namespace bead::model {
namespace {

TEST(LtiResponse, MatchesTheExactSimulationOnUnevenSampling) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(0.6, 1.4), level(80.0, 120.0);
  std::vector<double> t, u;
  double time = 0.0, v = 0.0;
  for (int i = 0; i < 6000; ++i) {
    if (i >= 50 && i % 37 == 0) v = level(rng);  // at rest (0) for the first 50 samples
    t.push_back(time);
    u.push_back(v);
    time += 0.005 * jitter(rng);
  }
  const TransferFunction tf = ThesisRpmToFlow(0.1537);
  const std::vector<double> exact = Simulate(tf, t, u);
  const std::vector<double> walked = Predict(tf, 0.0, t, u, {});  // steady at u[0] = 0: rest
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    scale = std::max(scale, std::abs(exact[i]));
    worst = std::max(worst, std::abs(exact[i] - walked[i]));
  }
  EXPECT_LT(worst, 1e-9 * scale) << "worst " << worst << " of " << scale;
}

TEST(LtiResponse, SlowAndFastPolesAndLongGaps) {
  // A fast pole (|A| q well past the short-step bound) and steps up to 5x
  // the mean (gaps): the walk falls back to whole steps and stays exact.
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> step(0.002, 0.05), level(-1.0, 1.0);
  std::vector<double> t, u;
  double time = 0.0, v = 0.0;
  for (int i = 0; i < 3000; ++i) {
    if (i >= 20 && i % 23 == 0) v = level(rng);
    t.push_back(time);
    u.push_back(v);
    time += step(rng);
  }
  const TransferFunction tf{{400.0, 2.0}, {1.0, 250.0, 3000.0, 500.0}, 0.031};  // poles near -237, -12.5, -0.17
  const std::vector<double> exact = Simulate(tf, t, u);
  const std::vector<double> walked = Predict(tf, 0.0, t, u, {});
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    scale = std::max(scale, std::abs(exact[i]));
    worst = std::max(worst, std::abs(exact[i] - walked[i]));
  }
  EXPECT_LT(worst, 1e-9 * scale) << "worst " << worst << " of " << scale;
}

}  // namespace
}  // namespace bead::model
