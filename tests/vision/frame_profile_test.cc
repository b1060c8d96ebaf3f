// Pixels to the laser plane, and whole frames to bead geometry: a bead of
// known shape on the laser plane, imaged through a known homography with a
// Gaussian stripe, measures as that shape within what the pixel spacing
// and the frame's rounding allow.
#include "libbead/vision/frame_profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/profile/profile_processor.h"
#include "tests/vision/render_stripe.h"

namespace bead::vision {
namespace {

using test::Apply;
const cv::Matx33d& kTrue = test::kTiltedCamera;

LaserPlaneMap TrueMap() {
  LaserPlaneMap m;
  m.mm_from_px = kTrue;
  return m;
}

// The plane-file form: no lens model; the stripe runs along the rows.
SensorModel TrueSensor() {
  SensorModel s;
  s.map = TrueMap();
  s.stripe.axis = StripeAxis::kRows;
  return s;
}

TEST(LaserPlaneMap, FitRecoversTheHomography) {
  std::vector<cv::Point2d> px, mm;
  for (double u : {50.0, 600.0, 1200.0})
    for (double v : {20.0, 200.0, 440.0}) px.push_back({u, v}), mm.push_back(Apply(kTrue, {u, v}));
  const LaserPlaneMap map = FitLaserPlaneMap(px, mm);
  // Elsewhere on the frame (corners extrapolated) to a small fraction of
  // a pixel (0.04 x 0.015 mm): exact data, so only the solver's numerics
  // are left (OpenCV's refinement stops near 1e-6 mm at the corners).
  for (double u : {0.0, 333.0, 1250.0})
    for (double v : {0.0, 111.0, 459.0}) {
      const cv::Point2d a = ToLaserPlane(map, {u, v}), b = Apply(kTrue, {u, v});
      EXPECT_NEAR(a.x, b.x, 1e-4) << u << ", " << v;
      EXPECT_NEAR(a.y, b.y, 1e-4) << u << ", " << v;
    }
}

TEST(LaserPlaneMap, RejectsTooFewLinedUpOrWrongPoints) {
  const std::vector<cv::Point2d> four_px = {{0, 0}, {100, 0}, {0, 100}, {100, 100}};
  std::vector<cv::Point2d> four_mm;
  for (const auto& p : four_px) four_mm.push_back(Apply(kTrue, p));
  auto message = [](const std::function<void()>& fit) {
    try {
      fit();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message([&] {
              FitLaserPlaneMap({four_px.begin(), four_px.end() - 1}, {four_mm.begin(), four_mm.end() - 1});
            }).find("needs 4 or more"),
            std::string::npos);
  const std::vector<cv::Point2d> line = {{0, 0}, {10, 10}, {20, 20}, {30, 30}, {40, 40}};
  std::vector<cv::Point2d> line_mm;
  for (const auto& p : line) line_mm.push_back(Apply(kTrue, p));
  EXPECT_NE(message([&] { FitLaserPlaneMap(line, line_mm); }).find("on one line"), std::string::npos);
  // Nine good pairs and one 2 mm off: the map cannot pass within 0.05 mm
  // of all of them.
  std::vector<cv::Point2d> px, mm;
  for (double u : {50.0, 600.0, 1200.0})
    for (double v : {20.0, 200.0, 440.0}) px.push_back({u, v}), mm.push_back(Apply(kTrue, {u, v}));
  px.push_back({900, 300});
  mm.push_back(Apply(kTrue, {900, 300}) + cv::Point2d(2.0, 0.0));
  EXPECT_NE(message([&] { FitLaserPlaneMap(px, mm); }).find("mm off the fitted map"), std::string::npos);
}

// test::Parabola12x3 (24 mm^2) through the camera: the geometry of the
// frame's profile. Edges err by at most H dx / 2 each (bead_geometry_test.cc) with
// dx = 0.04 mm a column; the 8-bit stripe centre errs by at most 0.036 px
// (stripe_test.cc's bound), 0.015 mm/px, over the 12 mm of the bead.
TEST(FrameProfile, ParabolicBeadMeasuresAsItsShape) {
  const test::Stripe stripe{[](int u) { return test::StripeRow(u, test::Parabola12x3); }, 1.6, 180.0, 12.0};
  const double dx = 0.04, height = 3.0, width = 12.0;
  for (int depth : {CV_32F, CV_8U}) {
    const cv::Mat frame = test::RenderStripe(470, 1251, stripe, depth);
    std::vector<float> x, z;
    StripeCentres stripe;
    FrameProfile(frame, TrueSensor(), stripe, x, z);
    ASSERT_EQ(x.size(), 1251u);
    for (std::size_t u = 0; u < x.size(); ++u) ASSERT_TRUE(std::isfinite(x[u]) && std::isfinite(z[u])) << u;
    const double stripe_mm = depth == CV_8U ? 0.036 * 0.015 : 0.0;
    const BeadGeometry g = MeasureProfile(ProfileView{x, z, 0.0, 0}, {-24.0, -12.0}, {12.0, 24.0});
    ASSERT_TRUE(g.valid()) << StatusName(g.status);
    EXPECT_NEAR(g.area_mm2, 24.0, height * dx + width * stripe_mm) << "depth " << depth;
    EXPECT_NEAR(g.width_mm, width, 2 * dx + 2 * stripe_mm / (height / 6.0 * 2)) << "depth " << depth;
    // Apex curvature 2 H / (W/2)^2; the robust maximum sits within 2 dx.
    EXPECT_NEAR(g.height_mm, height, 2 * height / 36.0 * (2 * dx) * (2 * dx) / 2 + stripe_mm) << "depth " << depth;
    EXPECT_NEAR(g.center_x_mm, 0.0, dx) << "depth " << depth;
    EXPECT_NEAR(g.reference.slope, 0.0, 1e-4) << "depth " << depth;
  }
}

}  // namespace
}  // namespace bead::vision
