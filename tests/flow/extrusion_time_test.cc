#include "libbead/flow/extrusion_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace bead {
namespace {

// p(t) = 100 t: the position 250 was reached at 2.5 s, whatever the profile time after it.
TEST(ExtrusionTime, LinearMotionIsExact) {
  std::vector<double> t, p;
  for (int i = 0; i <= 100; ++i) {
    t.push_back(0.1 * i);
    p.push_back(10.0 * i);
  }
  const ExtrusionTimeFinder f(t, p);
  EXPECT_NEAR(f.Find(7.3, 250.0), 2.5, 1e-12);
  EXPECT_NEAR(f.Find(2.56, 250.0), 2.5, 1e-12);
  EXPECT_TRUE(std::isnan(f.Find(5.0, -10.0)));  // before the log began
  EXPECT_NEAR(f.PositionAt(0.25), 25.0, 1e-12);
}

// A stop: the wheel stood at 300 from 3 s to 5 s. The nozzle stood over 300
// until 5 s: that is when material there was last laid.
TEST(ExtrusionTime, StopGivesTheEndOfTheStop) {
  std::vector<double> t, p;
  for (int i = 0; i <= 100; ++i) {
    const double ti = 0.1 * i;
    t.push_back(ti);
    p.push_back(ti < 3 ? 100 * ti : (ti < 5 ? 300 : 300 + 100 * (ti - 5)));
  }
  const ExtrusionTimeFinder f(t, p);
  EXPECT_NEAR(f.Find(9.0, 300.0), 5.0, 1e-9);
  EXPECT_NEAR(f.Find(9.0, 350.0), 5.5, 1e-9);
  EXPECT_NEAR(f.Find(9.0, 250.0), 2.5, 1e-9);
}

// A reversal: forward to 500 at 5 s, back to 300 at 7 s, forward again.
// Position 400 was passed three times; the latest before 9.5 s was at 8 s.
TEST(ExtrusionTime, ReversalGivesTheLatestPass) {
  std::vector<double> t, p;
  for (int i = 0; i <= 100; ++i) {
    const double ti = 0.1 * i;
    t.push_back(ti);
    p.push_back(ti < 5 ? 100 * ti : (ti < 7 ? 500 - 100 * (ti - 5) : 300 + 100 * (ti - 7)));
  }
  const ExtrusionTimeFinder f(t, p);
  EXPECT_NEAR(f.Find(9.5, 400.0), 8.0, 1e-9);
  EXPECT_NEAR(f.Find(7.5, 400.0), 6.0, 1e-9);
  EXPECT_NEAR(f.Find(5.5, 400.0), 4.0, 1e-9);
}

// The block index changes no answer: over a log that runs forward, stands
// (whole blocks flat at a value a target hits exactly), runs backward and
// holds whole counts, every search gives the plain walk's time bit for bit
// (NaN where it is NaN), for targets at samples, between them, before the
// log and beyond it, and profile times anywhere.
TEST(ExtrusionTime, TheBlockIndexGivesThePlainWalksAnswer) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> t, p;
  double pos = 0;
  for (int i = 0; i < 5000; ++i) {
    t.push_back(0.002 * i + 1e-4 * u(rng));
    const int phase = (i / 700) % 4;  // forward, standing, backward, forward fast
    if (phase == 0) pos += std::floor(3 * u(rng));
    if (phase == 2) pos -= std::floor(2 * u(rng));
    if (phase == 3) pos += 5;
    p.push_back(pos);
  }
  const ExtrusionTimeFinder plain(t, p);
  ExtrusionTimeFinder indexed(t, p);
  indexed.BuildIndex();
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int found = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double tm = -0.5 + 11.0 * u(rng);
    double target = -50 + (pos + 100) * u(rng);
    if (trial % 3 == 0) target = p[static_cast<std::size_t>(u(rng) * (p.size() - 1))];  // a sample's value
    const double a = plain.Find(tm, target), b = indexed.Find(tm, target);
    ASSERT_TRUE(same(a, b) || (std::isnan(a) && std::isnan(b))) << tm << " " << target << ": " << a << " vs " << b;
    found += std::isfinite(a);
  }
  EXPECT_GT(found, 5000);  // the searches found crossings, not only NaN
}

}  // namespace
}  // namespace bead
