#include "libbead/flow/extrusion_time.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace bead
