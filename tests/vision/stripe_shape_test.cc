// What counts as the stripe and where its centre is: the axis (a camera
// mounted either way), the stripe-shape tests (a chessboard's squares and
// edges are no stripe), the several-peaks rules, and each sub-pixel method
// against frames of known centre.
#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/sim/stripe_frame.h"
#include "libbead/vision/stripe.h"
#include "tests/vision/render_stripe.h"

namespace bead::vision {
namespace {

double Wave(int u) { return 60.3 + 25.0 * std::sin(2.0 * M_PI * u / 157.0); }

StripeOptions With(StripeAxis axis, StripeMethod method = StripeMethod::kGaussian) {
  StripeOptions o;
  o.axis = axis;
  o.method = method;
  return o;
}

TEST(StripeAxis, ACameraTurnedAQuarterSeesTheSameStripe) {
  const cv::Mat across = test::RenderStripe(120, 400, {Wave, 1.8, 180.0, 12.0}, CV_32F);
  cv::Mat down;
  cv::transpose(across, down);
  StripeCentres a, d, a_auto, d_auto;
  FindStripe(across, With(StripeAxis::kRows), a);
  FindStripe(down, With(StripeAxis::kColumns), d);
  ASSERT_EQ(d.centres.size(), 400u);
  for (std::size_t k = 0; k < 400; ++k) EXPECT_EQ(a.centres[k], d.centres[k]) << k;
  EXPECT_EQ(d.Pixel(7).y, 7.0);
  EXPECT_FLOAT_EQ(static_cast<float>(d.Pixel(7).x), a.centres[7]);
  // auto keeps the axis that finds the stripe on more lines: along the
  // 400-pixel side, not across its 120 rows (where the wave crosses
  // each row twice or runs along it).
  FindStripe(across, {}, a_auto);
  FindStripe(down, {}, d_auto);
  EXPECT_EQ(a_auto.axis, StripeAxis::kRows);
  EXPECT_EQ(d_auto.axis, StripeAxis::kColumns);
  EXPECT_EQ(a_auto.stats.found, 400);
}

// Squares of 40 px, black 10 and white 70 grey levels, no stripe: a white
// square between black ones is 40 px wide at half height (not under
// max_width_px = 30), and an edge is a step (one side stays high): none
// is a stripe, whichever axis. With a stripe drawn across the board, it
// is found on every column, and nowhere off its centre.
TEST(StripeShape, ChessboardSquaresAndEdgesAreNoStripe) {
  cv::Mat board(240, 400, CV_32F);
  for (int v = 0; v < board.rows; ++v)
    for (int u = 0; u < board.cols; ++u) board.at<float>(v, u) = ((u / 40 + v / 40) % 2) ? 70.0f : 10.0f;
  StripeOptions o = With(StripeAxis::kAuto);
  o.max_width_px = 30.0;
  StripeCentres s;
  FindStripe(board, o, s);
  EXPECT_EQ(s.stats.found, 0) << Describe(s.stats);
  EXPECT_GT(s.stats.too_wide, 0) << Describe(s.stats);
  EXPECT_EQ(s.stats.lines, s.stats.no_peak + s.stats.too_wide + s.stats.at_border) << Describe(s.stats);

  const cv::Mat stripe = test::RenderStripe(240, 400, {[](int u) { return 100.3 + 0.1 * u; }, 1.8, 150.0, 0.0}, CV_32F);
  FindStripe(board + stripe, o, s);
  ASSERT_EQ(s.axis, StripeAxis::kRows);
  // Where it rides along an edge it may look flat-topped (one side's
  // floor is the step's top) and be lost: a few columns.
  EXPECT_GE(s.stats.found, 390) << Describe(s.stats);
  // Away from the squares' horizontal edges (rows 80, 120, 160) by 3
  // sigma the stripe stands on one level, but its floor (the darkest
  // sample within reach) may be the next square's: the three-point
  // Gaussian on a pedestal errs by a few hundredths of a pixel at most.
  // Riding on an edge the stripe sits on a step: the floor is the step's
  // top and the peak is skewed, by less than the stripe's sigma.
  for (int u = 0; u < 400; ++u) {
    const double c = 100.3 + 0.1 * u, edge = 40.0 * std::round(c / 40.0);
    const double found = s.centres[static_cast<std::size_t>(u)];
    if (std::abs(c - edge) > 3 * 1.8) {
      EXPECT_NEAR(found, c, 0.02) << u;
    } else if (!std::isnan(found)) {
      EXPECT_NEAR(found, c, 1.8) << u;
    }
  }
}

TEST(StripeShape, AHotPixelIsTooNarrowAndAStripeOffTheFrameIsAtTheBorder) {
  cv::Mat frame(50, 60, CV_32F, cv::Scalar(10.0f));
  frame.at<float>(25, 3) = 200.0f;  // one pixel: no width
  frame.row(0).colRange(30, 60).setTo(200.0f);
  frame.row(1).colRange(30, 60).setTo(120.0f);
  StripeCentres s;
  FindStripe(frame, With(StripeAxis::kRows), s);
  EXPECT_EQ(s.stats.found, 0);
  EXPECT_EQ(s.stats.too_narrow, 1) << Describe(s.stats);
  EXPECT_EQ(s.stats.at_border, 30) << Describe(s.stats);
  EXPECT_EQ(s.stats.no_peak, 29) << Describe(s.stats);
}

// A stripe (peak 180) and its reflection (90) 60 rows below it.
TEST(StripePeaks, TheRuleChoosesAmongSeveral) {
  sim::StripeFrameSpec spec;
  spec.snr_db = INFINITY, spec.reflection = 0.5, spec.reflection_offset_px = 60.0, spec.centre_row = 80.0;
  spec.peak = 180.0, spec.wave_px = 5.0;
  std::vector<std::uint8_t> px;
  std::vector<double> truth;
  sim::RenderStripeFrame(spec, 1, px, truth);
  const cv::Mat frame(spec.rows, spec.cols, CV_8UC1, px.data());
  auto mean_offset = [&](PeakRule rule) {
    StripeOptions o = With(StripeAxis::kRows);
    o.rule = rule;
    StripeCentres s;
    FindStripe(frame, o, s);
    EXPECT_EQ(s.stats.found, spec.cols);
    EXPECT_EQ(s.stats.several, spec.cols);
    double sum = 0.0;
    for (int u = 0; u < spec.cols; ++u)
      sum += s.centres[static_cast<std::size_t>(u)] - truth[static_cast<std::size_t>(u)];
    return sum / spec.cols;
  };
  EXPECT_NEAR(mean_offset(PeakRule::kStrongest), 0.0, 0.05);
  EXPECT_NEAR(mean_offset(PeakRule::kFirst), 0.0, 0.05);
  EXPECT_NEAR(mean_offset(PeakRule::kLast), 60.0, 0.05);
  EXPECT_NEAR(mean_offset(PeakRule::kNearest), 0.0, 0.05);  // the first line's strongest, then followed
}

// Float frames (no rounding) of a point-sampled Gaussian, sigma 2 px.
// The Gaussian estimator is exact. The parabola through three samples of
// a Gaussian errs by at most 0.03 px at sigma = 2 (its bias is odd in
// the sub-pixel offset, zero at 0 and 1/2: Fisher and Naidu 1996, fig. 2).
// The centre of gravity above half height takes whole samples inside
// +-1.18 sigma: the samples entering and leaving at the edge shift it by
// at most one sample's weight share, under 0.1 px here. Steger's estimate
// is the zero of the derivative of the column's profile smoothed by a
// Gaussian of s: a Gaussian of sqrt(sigma^2 + s^2), symmetric about the
// centre, so only the sampled kernel's and the Taylor step's errors
// remain: 0.02 px.
TEST(StripeMethods, EachFindsAGaussiansCentreWithinItsSamplingBias) {
  const cv::Mat frame = test::RenderStripe(120, 400, {Wave, 2.0, 180.0, 12.0}, CV_32F);
  const std::pair<StripeMethod, double> methods[] = {{StripeMethod::kGaussian, 2e-5},
                                                     {StripeMethod::kParabolic, 0.03},
                                                     {StripeMethod::kCentreOfGravity, 0.1},
                                                     {StripeMethod::kSteger, 0.02}};
  for (const auto& [method, bound] : methods) {
    StripeCentres s;
    FindStripe(frame, With(StripeAxis::kRows, method), s);
    EXPECT_EQ(s.stats.found, 400) << Name(method) << ": " << Describe(s.stats);
    double worst = 0.0, sum = 0.0;
    for (int u = 0; u < 400; ++u) {
      const double e = s.centres[static_cast<std::size_t>(u)] - Wave(u);
      worst = std::max(worst, std::abs(e)), sum += e;
    }
    EXPECT_LE(worst, bound) << Name(method);
    EXPECT_NEAR(sum / 400, 0.0, bound / 4) << Name(method) << ": the bias is odd, so it averages out";
  }
}

// A saturated stripe 13 px wide (peak 1000 clipped at 255, sigma 4): the
// flat top is symmetric about the centre, so the centre of gravity and
// Steger (scale from the measured width, sigma >= w / sqrt(3)) find it to
// within the rounding of the edges; the plateau's middle is within half a
// pixel.
TEST(StripeMethods, SaturatedWideStripe) {
  const cv::Mat frame = test::RenderStripe(120, 400, {Wave, 4.0, 1000.0, 12.0}, CV_8U);
  const std::pair<StripeMethod, double> methods[] = {
      {StripeMethod::kGaussian, 0.5}, {StripeMethod::kCentreOfGravity, 0.1}, {StripeMethod::kSteger, 0.1}};
  for (const auto& [method, bound] : methods) {
    StripeCentres s;
    FindStripe(frame, With(StripeAxis::kRows, method), s);
    EXPECT_EQ(s.stats.found, 400) << Name(method) << ": " << Describe(s.stats);
    EXPECT_EQ(s.stats.saturated, 400) << Name(method);
    for (int u = 0; u < 400; ++u)
      EXPECT_NEAR(s.centres[static_cast<std::size_t>(u)], Wave(u), bound) << Name(method) << " " << u;
  }
}

// A straight stripe at 30 degrees to the rows: each column crosses it at
// c(u) = 40 + tan(30 deg) u exactly; the cross-section along a column is
// a Gaussian of sigma / cos(30 deg) centred there, so every method stays
// within its bound above (Steger: from the 2-D Hessian, intersecting the
// tangent with the column).
TEST(StripeMethods, TiltedStripe) {
  const double slope = std::tan(M_PI / 6);
  const double sigma = 2.0 / std::cos(M_PI / 6);
  const cv::Mat frame =
      test::RenderStripe(300, 400, {[&](int u) { return 40.0 + slope * u; }, sigma, 180.0, 12.0}, CV_32F);
  for (StripeMethod method : {StripeMethod::kGaussian, StripeMethod::kSteger}) {
    StripeCentres s;
    FindStripe(frame, With(StripeAxis::kRows, method), s);
    EXPECT_EQ(s.stats.found, 400) << Name(method) << ": " << Describe(s.stats);
    for (int u = 0; u < 400; ++u)
      EXPECT_NEAR(s.centres[static_cast<std::size_t>(u)], 40.0 + slope * u, 0.03) << Name(method) << " " << u;
  }
}

TEST(StripeOptions, NamesRoundTripAndBadOnesAreRefused) {
  for (StripeMethod m :
       {StripeMethod::kCentreOfGravity, StripeMethod::kGaussian, StripeMethod::kParabolic, StripeMethod::kSteger})
    EXPECT_EQ(ParseStripeMethod(Name(m)), m);
  for (PeakRule r : {PeakRule::kStrongest, PeakRule::kWidest, PeakRule::kFirst, PeakRule::kLast, PeakRule::kNearest})
    EXPECT_EQ(ParsePeakRule(Name(r)), r);
  for (StripeAxis a : {StripeAxis::kAuto, StripeAxis::kRows, StripeAxis::kColumns})
    EXPECT_EQ(ParseStripeAxis(Name(a)), a);
  try {
    ParseStripeMethod("centroid");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cog, gaussian, parabolic, steger"), std::string::npos) << e.what();
  }
  StripeOptions o;
  o.max_width_px = 0.5;
  StripeCentres s;
  EXPECT_THROW(FindStripe(cv::Mat(5, 5, CV_8UC1, cv::Scalar(0)), o, s), Error);
}

}  // namespace
}  // namespace bead::vision
