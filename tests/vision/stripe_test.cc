// The stripe's centre in each image column, from frames rendered with a
// Gaussian stripe of known centre: exact in float frames (the estimator is
// exact for a sampled Gaussian), within the bound 8-bit rounding allows,
// within half a pixel on a saturated plateau; no stripe where there is none.
#include "libbead/vision/stripe.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "libbead/core/error.h"
#include "tests/vision/render_stripe.h"

namespace bead::vision {
namespace {

double Centre(int u) { return 60.3 + 25.0 * std::sin(2.0 * M_PI * u / 157.0); }

// The stripe runs along the rows: one centre per column.
StripeOptions Across(StripeMethod method = StripeMethod::kGaussian) {
  StripeOptions o;
  o.axis = StripeAxis::kRows;
  o.method = method;
  return o;
}

void CentreRows(const cv::Mat& frame, const StripeOptions& options, std::vector<float>& rows) {
  vision::StripeCentres found;
  FindStripe(frame, options, found);
  rows = found.centres;
}

TEST(Stripe, FloatFrameGivesTheExactCentre) {
  const test::Stripe stripe{Centre, 1.8, 180.0, 12.0};
  const cv::Mat frame = test::RenderStripe(120, 400, stripe, CV_32F);
  std::vector<float> rows;
  CentreRows(frame, Across(), rows);
  ASSERT_EQ(rows.size(), 400u);
  // Float intensities carry a relative rounding of 6e-8; through the
  // logarithms and the curvature 1 / sigma^2 that moves the centre by
  // ~1e-6 px; the centre itself is a float near 60 (4e-6 px).
  for (int u = 0; u < 400; ++u) EXPECT_NEAR(rows[static_cast<std::size_t>(u)], Centre(u), 2e-5) << "column " << u;
}

TEST(Stripe, EightBitRoundingMovesTheCentreWithinItsBound) {
  const double sigma = 1.8, peak = 180.0;
  const test::Stripe stripe{Centre, sigma, peak, 12.0};
  const cv::Mat frame = test::RenderStripe(120, 400, stripe, CV_8U);
  std::vector<float> rows;
  CentreRows(frame, Across(), rows);
  // The estimator is d = 0.5 N / D with N = ln a - ln d and D = ln a -
  // 2 ln c + ln d = -1 / sigma^2. Rounding moves each sample by at most
  // 0.5 grey level: ln a and ln d by 0.5 / a_min with a_min = peak
  // exp(-1.5^2 / (2 sigma^2)) (a neighbour lies at most 1.5 px from the
  // centre), ln c by 0.5 / peak. So |dN| <= 2e, |dD| <= 2e + 2 e_c and
  // |d delta| <= (0.5 |dN| + 0.5 |dD|) / (|D| - |dD|) (|delta| <= 0.5).
  const double e = 0.5 / (peak * std::exp(-1.5 * 1.5 / (2 * sigma * sigma))), e_c = 0.5 / peak;
  const double d_n = 2 * e, d_d = 2 * e + 2 * e_c, curvature = 1.0 / (sigma * sigma);
  const double bound = (0.5 * d_n + 0.5 * d_d) / (curvature - d_d);
  double worst = 0.0;
  for (int u = 0; u < 400; ++u) {
    const double error = std::abs(rows[static_cast<std::size_t>(u)] - Centre(u));
    EXPECT_LE(error, bound) << "column " << u;
    worst = std::max(worst, error);
  }
  EXPECT_GT(worst, 0.0);  // 8-bit rounding does move it
}

TEST(Stripe, SaturatedPeakIsTheMiddleOfItsPlateau) {
  // Peak 400 over a background of 10 clips at 255 over +-sigma
  // sqrt(2 ln(400 / 245)) ~ 2 px: the plateau's integer rows run from
  // ceil(c - r) to floor(c + r), whose middle is within half a pixel of c.
  const test::Stripe stripe{Centre, 2.0, 400.0, 10.0};
  std::vector<float> rows;
  CentreRows(test::RenderStripe(120, 400, stripe, CV_8U), Across(), rows);
  for (int u = 0; u < 400; ++u) EXPECT_NEAR(rows[static_cast<std::size_t>(u)], Centre(u), 0.5) << "column " << u;
  // Sixteen-bit frames saturate at 65535.
  const test::Stripe bright{Centre, 2.0, 1e5, 10.0};
  CentreRows(test::RenderStripe(120, 400, bright, CV_16U), Across(), rows);
  for (int u = 0; u < 400; ++u) EXPECT_NEAR(rows[static_cast<std::size_t>(u)], Centre(u), 0.5) << "column " << u;
}

TEST(Stripe, NoStripeWhereThereIsNone) {
  // Columns 0-99 dark (the stripe 15 grey levels high, under the 20 the
  // options ask for), 100-199 lit, 200-299 with the stripe on the first row.
  const test::Stripe faint{Centre, 1.8, 15.0, 12.0};
  cv::Mat frame = test::RenderStripe(120, 300, faint, CV_32F);
  const test::Stripe lit{Centre, 1.8, 180.0, 12.0};
  test::RenderStripe(120, 300, lit, CV_32F).colRange(100, 200).copyTo(frame.colRange(100, 200));
  frame.colRange(200, 300).setTo(12.0f);
  frame.row(0).colRange(200, 300).setTo(200.0f);
  std::vector<float> rows;
  CentreRows(frame, Across(), rows);
  for (int u = 0; u < 300; ++u) {
    const float r = rows[static_cast<std::size_t>(u)];
    if (u >= 100 && u < 200)
      EXPECT_NEAR(r, Centre(u), 2e-5) << "column " << u;
    else
      EXPECT_TRUE(std::isnan(r)) << "column " << u << ": " << r;
  }
}

TEST(Stripe, RejectsFramesItCannotRead) {
  std::vector<float> rows;
  EXPECT_THROW(CentreRows(cv::Mat(), Across(), rows), Error);
  try {
    CentreRows(cv::Mat(10, 10, CV_8UC3, cv::Scalar(0, 0, 0)), Across(), rows);
    ADD_FAILURE() << "a colour frame was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("8UC3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bead::vision
