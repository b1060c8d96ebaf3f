#include "libbead/series/hampel.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bead {
namespace {

// MATLAB: x = sin(2*pi*(0:99)/100); x(6) = 2; x(20) = -2; hampel(x, 3, 3)
// flags exactly samples 6 and 20 (1-based) and puts the window medians there.
TEST(Hampel, MatlabExampleFlagsExactlySixAndTwenty) {
  std::vector<double> x(100);
  for (int i = 0; i < 100; ++i) x[i] = std::sin(2 * M_PI * i / 100.0);
  x[5] = 2;
  x[19] = -2;
  const HampelResult r = Hampel(x, 3, 3.0);
  EXPECT_EQ(r.outliers, 2);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(r.outlier[i], i == 5 || i == 19) << i;
  // The replacement is the median of x(3:9) (1-based), which holds the spike.
  std::vector<double> w(x.begin() + 2, x.begin() + 9);
  std::sort(w.begin(), w.end());
  EXPECT_DOUBLE_EQ(r.y[5], w[3]);
}

// Strict inequality: window {-1, 0, 0, 1, t} has median 0 and MAD 1, so
// sigma = 1.4826022185; t = 3 sigma exactly is kept, the next double is not.
TEST(Hampel, ThresholdIsStrict) {
  const double sigma = 1.4826022185;
  const double at = 3.0 * sigma;
  EXPECT_EQ(Hampel({-1.0, 0.0, 0.0, 1.0, at}, 4, 3.0).outlier[4], 0);
  EXPECT_EQ(Hampel({-1.0, 0.0, 0.0, 1.0, std::nextafter(at, 10.0)}, 4, 3.0).outlier[4], 1);
}

TEST(Hampel, GapsStayGapsAndDoNotPoisonWindows) {
  std::vector<double> x = {1, 1.1, NAN, 0.9, 50, 1.0, NAN, 1.05, 0.95};
  const HampelResult r = Hampel(x, 3, 3.0);
  EXPECT_TRUE(std::isnan(r.y[2]));
  EXPECT_TRUE(std::isnan(r.y[6]));
  EXPECT_EQ(r.outlier[4], 1);
  EXPECT_EQ(r.outliers, 1);
}

}  // namespace
}  // namespace bead
