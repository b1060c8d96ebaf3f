#include "libbead/series/savgol.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"

namespace bead {
namespace {

const std::vector<double> kX = {2, 2, 5, 2, 1, 0, 1, 4, 9};

void ExpectNear(const std::vector<double>& got, const std::vector<double>& want, double tol) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], tol) << "index " << i;
}

// Values from the issue (SciPy savgol_filter), to 1e-12.
TEST(Savgol, InterpMatchesScipy) {
  SavgolOptions o;
  ExpectNear(SavgolFilter(kX, o),
             {1.657142857143, 3.171428571429, 3.542857142857, 2.857142857143, 0.657142857143, 0.171428571429, 1, 4, 9},
             1e-12);
  o.deriv = 1;
  o.delta = 0.5;
  ExpectNear(SavgolFilter(kX, o), {4.171428571429, 1.885714285714, -0.4, -1.6, -2, 0.8, 4, 8, 12}, 1e-12);
}

// The padded modes are a plain convolution of the padded series with the
// 5-point quadratic weights (-3, 12, 17, 12, -3) / 35 (Savitzky & Golay's
// table); the pads are built here by hand for each mode.
TEST(Savgol, PaddedModesAreConvolutionsOfTheirPads) {
  const double w[5] = {-3 / 35.0, 12 / 35.0, 17 / 35.0, 12 / 35.0, -3 / 35.0};
  auto convolve = [&](std::vector<double> padded) {
    std::vector<double> y;
    for (std::size_t i = 0; i + 4 < padded.size(); ++i) {
      double acc = 0;
      for (int j = 0; j < 5; ++j) acc += w[j] * padded[i + j];
      y.push_back(acc);
    }
    return y;
  };
  auto pad = [&](double a, double b, double c, double d) {
    std::vector<double> p = {a, b};
    p.insert(p.end(), kX.begin(), kX.end());
    p.push_back(c);
    p.push_back(d);
    return p;
  };
  SavgolOptions o;
  o.mode = SavgolMode::kMirror;  // d c b | a b c d | c b a
  ExpectNear(SavgolFilter(kX, o), convolve(pad(5, 2, 4, 1)), 1e-12);
  o.mode = SavgolMode::kNearest;
  ExpectNear(SavgolFilter(kX, o), convolve(pad(2, 2, 9, 9)), 1e-12);
  o.mode = SavgolMode::kWrap;
  ExpectNear(SavgolFilter(kX, o), convolve(pad(4, 9, 2, 2)), 1e-12);
  o.mode = SavgolMode::kConstant;
  o.cval = 0.5;
  ExpectNear(SavgolFilter(kX, o), convolve(pad(0.5, 0.5, 0.5, 0.5)), 1e-12);
  // SciPy's documented nearest-mode result, to its two printed decimals.
  o.mode = SavgolMode::kNearest;
  ExpectNear(SavgolFilter(kX, o), {1.74, 3.03, 3.54, 2.86, 0.66, 0.17, 1., 4.6, 7.97}, 0.005);
}

// Long windows and high orders stay well conditioned: a polynomial of the
// filter's order passes through unchanged, and its derivative is exact.
TEST(Savgol, LongWindowHighOrderReproducesPolynomials) {
  std::vector<double> x, dx;
  const double h = 0.01;
  for (int i = 0; i < 400; ++i) {
    const double t = -2.0 + h * i;
    double p = 0, dp = 0;
    for (int k = 0; k <= 10; ++k) {
      p += std::pow(t, k) / (k + 1);
      if (k) dp += k * std::pow(t, k - 1) / (k + 1);
    }
    x.push_back(p);
    dx.push_back(dp);
  }
  SavgolOptions o;
  o.window = 201;
  o.order = 10;
  const auto y = SavgolFilter(x, o);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(y[i], x[i], 1e-7 * (1 + std::abs(x[i]))) << i;
  o.deriv = 1;
  o.delta = h;
  const auto d = SavgolFilter(x, o);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(d[i], dx[i], 1e-5 * (1 + std::abs(dx[i]))) << i;
}

TEST(Savgol, RejectsEvenWindowsAndShortSeries) {
  SavgolOptions o;
  o.window = 4;
  EXPECT_THROW(SavgolFilter(kX, o), Error);
  o.window = 11;
  EXPECT_THROW(SavgolFilter(kX, o), Error);  // interp needs window samples
  o.window = 5;
  o.order = 5;
  EXPECT_THROW(SavgolFilter(kX, o), Error);
  EXPECT_THROW(ParseSavgolMode("reflect"), Error);
  EXPECT_EQ(ParseSavgolMode("wrap"), SavgolMode::kWrap);
}

// A line with gaps: short gaps are bridged, long ones split; the line comes
// through exactly and NaN stays where it was.
TEST(Savgol, GapsDoNotSpreadNaN) {
  std::vector<double> x;
  for (int i = 0; i < 60; ++i) x.push_back(0.5 * i + 1);
  x[10] = x[11] = NAN;                       // short gap: filled
  for (int i = 30; i < 45; ++i) x[i] = NAN;  // long gap: splits
  SavgolOptions o;
  o.window = 7;
  const auto y = SavgolFilterGaps(x, o, 3);
  for (int i = 0; i < 60; ++i) {
    if (std::isnan(x[i]))
      EXPECT_TRUE(std::isnan(y[i])) << i;
    else
      EXPECT_NEAR(y[i], 0.5 * i + 1, 1e-12) << i;
  }
}

}  // namespace
}  // namespace bead
