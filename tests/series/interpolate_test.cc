#include "libbead/series/interpolate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace bead {
namespace {

// The search started from a hint is std::upper_bound's answer whatever the
// hint: on times with repeats (a log that stamps two samples alike), for
// queries at samples, between them, before and beyond the record, and with
// hints anywhere from 0 to past the end.
TEST(Interpolate, UpperBoundNearIsUpperBoundFromAnyHint) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> t;
  double now = 0;
  for (int i = 0; i < 3000; ++i) {
    if (u(rng) > 0.05) now += 0.002 * u(rng);  // 5 % repeat the last time
    t.push_back(now);
  }
  for (int trial = 0; trial < 50000; ++trial) {
    double x = -0.1 + (now + 0.2) * u(rng);
    if (trial % 4 == 0) x = t[static_cast<std::size_t>(u(rng) * t.size())];  // exactly a sample's time
    const std::size_t hint = static_cast<std::size_t>(u(rng) * (t.size() + 3));
    const std::size_t want = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), x) - t.begin());
    ASSERT_EQ(UpperBoundNear(t.data(), t.size(), x, hint), want) << "x " << x << " hint " << hint;
  }
  EXPECT_EQ(UpperBoundNear(t.data(), 0, 1.0, 5), 0u);  // nothing to search
}

// Interpolating along queries that run nearly in order, the hint carried
// from one to the next, gives InterpolateLinear's value bit for bit (the
// same bracketing samples, the same arithmetic), NaN for NaN.
TEST(Interpolate, NearGivesInterpolateLinearsValueBitForBit) {
  std::mt19937_64 rng(12);
  std::normal_distribution<double> jitter(0.0, 0.003);
  std::vector<double> t, y;
  for (int i = 0; i < 2000; ++i) {
    t.push_back(0.002 * i);
    y.push_back(std::sin(0.01 * i) + 0.1 * jitter(rng));
  }
  std::size_t hint = 0;
  for (int i = -50; i < 2100; ++i) {
    double x = 0.002 * i + jitter(rng);  // backward steps now and then
    if (i == 700) x = std::nan("");
    const double a = InterpolateLinear(t, y, x), b = InterpolateLinearNear(t, y, x, hint);
    ASSERT_TRUE(std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)))
        << x << ": " << a << " vs " << b;
  }
}

}  // namespace
}  // namespace bead
