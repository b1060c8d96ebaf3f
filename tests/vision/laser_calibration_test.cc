// `bead calibrate laser` against rendered truth: a camera of known lens
// sees a chessboard at six poses with a laser sheet across it; the
// calibration must give back the camera and the plane, and the map from
// pixels to the plane must measure true distances on it.
#include "calibration/laser_calibration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/vision/laser_plane.h"
#include "tests/vision/render_board.h"

namespace bead::calibration {
namespace {

struct Pose {
  cv::Vec3d rvec, tvec;
};

// Tilts (degrees about x, then y) and where the board's middle sits,
// camera coordinates (mm): all in view, the sheet (x ~ 0 at z = 300)
// across the paper.
std::vector<Pose> Poses() {
  const double tilt[8][2] = {{0, 0}, {30, 0}, {-30, 5}, {0, 30}, {15, -30}, {-25, -20}, {20, 25}, {-10, 15}};
  const double middle[8][3] = {{-10, 0, 220}, {10, -10, 210}, {0, 10, 240}, {-15, 5, 230},
                               {5, -5, 200},  {15, 10, 220},  {-5, 0, 250}, {0, -10, 215}};
  std::vector<Pose> out;
  for (int i = 0; i < 8; ++i) {
    cv::Matx33d rx, ry;
    cv::Rodrigues(cv::Vec3d(tilt[i][0] * M_PI / 180, 0, 0), rx);
    cv::Rodrigues(cv::Vec3d(0, tilt[i][1] * M_PI / 180, 0), ry);
    const cv::Matx33d r = ry * rx;
    Pose p;
    cv::Rodrigues(r, p.rvec);
    p.tvec = cv::Vec3d(middle[i][0], middle[i][1], middle[i][2]) - r * cv::Vec3d(30, 25, 0);
    out.push_back(p);
  }
  return out;
}

std::vector<cv::Mat> Render(const test::BoardScene& scene) {
  std::vector<cv::Mat> frames;
  for (const Pose& p : Poses()) frames.push_back(test::RenderBoard(scene, p.rvec, p.tvec));
  return frames;
}

const std::vector<cv::Mat>& Frames() {
  static const std::vector<cv::Mat> frames = Render({});
  return frames;
}

std::vector<std::string> Names(std::size_t n) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back("view" + std::to_string(i));
  return out;
}

const Board kBoard{8, 7, 10.0};

double AngleDeg(const cv::Vec4d& a, const cv::Vec4d& b) {
  const cv::Vec3d na(a[0], a[1], a[2]), nb(b[0], b[1], b[2]);
  return std::acos(std::min(1.0, std::abs(na.dot(nb)) / (cv::norm(na) * cv::norm(nb)))) * 180 / M_PI;
}

// The sheet's points seen from the camera, mapped back: distances on the
// plane between the (x, z) the sensor gives must be the 3-D ones.
double WorstDistanceErrorMm(const vision::SensorModel& sensor, const test::BoardScene& scene) {
  // The scene's sheet, 0.8 x + 0.6 z = 132: through (0, 0, 220), spanned
  // by y and (-0.6, 0, 0.8); a grid over where the boards were.
  std::vector<cv::Point3d> truth;
  for (double a = -40; a <= 40; a += 20)
    for (double b = -30; b <= 30; b += 15) truth.emplace_back(-0.6 * b, a, 220.0 + 0.8 * b);
  std::vector<cv::Point2d> px;
  cv::projectPoints(truth, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), scene.camera, scene.distortion, px);
  vision::Undistort(sensor.camera, px);
  std::vector<cv::Point2d> mm;
  for (const cv::Point2d& p : px) mm.push_back(vision::ToLaserPlane(sensor.map, p));
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i)
    for (std::size_t j = i + 1; j < truth.size(); ++j)
      worst = std::max(worst, std::abs(cv::norm(mm[i] - mm[j]) - cv::norm(truth[i] - truth[j])));
  return worst;
}

// The rendering's own error: hard-edged squares sampled by 3 x 3 rays a
// pixel and rounded to 8 bits leave the corners good to about 0.2 px
// (the fit's reprojection RMS), so the camera is known to its reported
// standard deviations (fx to about 0.4 %). Depth from a calibrated camera
// scales with the focal length: the plane's distance and lengths measured
// on it carry the same relative error, so they are held to 4 of fx's
// relative standard deviations (plus 0.05 mm for the stripe centres).
// The plane's tilt: the views span about 100 mm of it, 0.5 degrees is
// 0.9 mm across that, several times the depth bound.
TEST(LaserCalibration, RecoversCameraAndPlaneFromRenderedBoards) {
  const test::BoardScene scene;
  const LaserCalibration c = CalibrateLaser(Frames(), Names(8), kBoard, {});
  EXPECT_EQ(c.images_used, 8);
  EXPECT_LT(c.camera.rms_px, 0.3);
  const auto& k = c.sensor.camera.matrix;
  for (int i : {0, 1}) EXPECT_NEAR(k(i, i), scene.camera(i, i), 4 * c.camera.sd[static_cast<std::size_t>(i)]) << i;
  for (int i : {0, 1}) EXPECT_NEAR(k(i, 2), scene.camera(i, 2), 4 * c.camera.sd[static_cast<std::size_t>(2 + i)]) << i;
  const double relative = c.camera.sd[0] / k(0, 0);
  EXPECT_LT(relative, 0.01);
  EXPECT_NEAR(c.sensor.camera.distortion[0], scene.distortion[0], 4 * c.camera.sd[4]);
  EXPECT_LT(AngleDeg(c.sensor.plane, scene.laser), 0.5);
  EXPECT_NEAR(c.sensor.plane[3], std::abs(scene.laser[3]), 4 * relative * std::abs(scene.laser[3]) + 0.05);
  EXPECT_LT(WorstDistanceErrorMm(c.sensor, scene), 4 * relative * 100.0 + 0.05);
  EXPECT_EQ(c.sensor.stripe.axis, vision::StripeAxis::kColumns);  // the sheet runs down the image
  for (const LaserView& v : c.views) {
    EXPECT_TRUE(v.board) << v.name;
    EXPECT_GT(v.plane_points, 200) << v.name;
    EXPECT_LT(std::abs(v.plane_mean_mm), 3 * c.plane.sigma_mm) << v.name;
  }
}

// The paper ends 15 mm past the squares and the stripe goes on over a
// table 6 mm lower: those points are off the board's plane by up to 6 mm
// along the sheet. They must be left out (counted per view), and the
// plane stay as good as without them.
TEST(LaserCalibration, StripeOffThePlateIsLeftOutAndCounted) {
  test::BoardScene scene;
  scene.margin_mm = 15.0, scene.table_drop_mm = 6.0;
  const std::vector<cv::Mat> frames = Render(scene);
  const LaserCalibration c = CalibrateLaser(frames, Names(8), kBoard, {});
  int outliers = 0;
  for (const LaserView& v : c.views) outliers += v.outliers;
  EXPECT_GT(outliers, 200);
  const double relative = c.camera.sd[0] / c.sensor.camera.matrix(0, 0);
  EXPECT_LT(AngleDeg(c.sensor.plane, scene.laser), 0.5);
  EXPECT_LT(WorstDistanceErrorMm(c.sensor, scene), 4 * relative * 100.0 + 0.05);
  // With a margin, the far points are not even tried.
  LaserCalibrationOptions near;
  near.board_margin_mm = 10.0;
  const LaserCalibration m = CalibrateLaser(frames, Names(8), kBoard, near);
  int beyond = 0;
  for (const LaserView& v : m.views) beyond += v.beyond_margin;
  EXPECT_GT(beyond, outliers);
  EXPECT_LT(AngleDeg(m.sensor.plane, scene.laser), 0.5);
}

TEST(LaserCalibration, TooFewBoardsIsAnErrorThatSaysSo) {
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(30));
  const std::vector<cv::Mat> frames = {Frames()[0], Frames()[1], blank};
  try {
    CalibrateLaser(frames, Names(3), kBoard, {});
    ADD_FAILURE() << "calibrated from two boards";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("found in 2 image(s)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseBoard("8x8", 10.0), Error);
  EXPECT_THROW(ParseBoard("8 x 7", 10.0), Error);
  EXPECT_THROW(ParseBoard("8x7", 0.0), Error);
  EXPECT_EQ(ParseBoard("8x7", 10.0).InnerCorners(), cv::Size(7, 6));
}

}  // namespace
}  // namespace bead::calibration
