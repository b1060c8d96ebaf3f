// The sensor file: what is written is read back to the last digit the
// writer keeps (12 significant: 1e-12 relative), and every malformed key is
// an error naming the file, the line and the key.
#include "libbead/vision/sensor_yaml.h"

#include <gtest/gtest.h>

#include "tests/support/expect_rejected.h"
#include "tests/support/temp_dir.h"

namespace bead::vision {
namespace {

SensorModel Example() {
  SensorModel s;
  s.camera.matrix = cv::Matx33d(2339.359351446, 0, 659.660839908, 0, 2346.950461822, 500.174565853, 0, 0, 1);
  s.camera.distortion = {-0.0210786424879, -0.517243257678, -0.00112499548156, 0.00156823943797, 0.0};
  s.camera.image_size = cv::Size(1280, 1024);
  const cv::Vec3d n = cv::normalize(cv::Vec3d(-0.8716, -0.2244, -0.4358));
  s.plane = cv::Vec4d(n[0], n[1], n[2], 159.41341955);
  s.map.mm_from_px =
      cv::Matx33d(-0.0982678, 0.468046, -152.524, 0.876790, 0.221846, -910.309, 0.00262032, 0.000672566, 1);
  s.stripe.axis = StripeAxis::kColumns;
  s.stripe.method = StripeMethod::kSteger;
  s.stripe.rule = PeakRule::kNearest;
  s.stripe.threshold = 180;
  return s;
}

TEST(SensorYaml, WhatIsWrittenIsRead) {
  test::TempDir dir;
  const SensorModel s = Example();
  WriteSensorYaml(dir / "sensor.yaml", s, "{board: 8x7, images_used: 7}");
  const SensorModel r = ReadSensorYaml(dir / "sensor.yaml");
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(r.camera.matrix.val[i], s.camera.matrix.val[i], 1e-12 * std::abs(s.camera.matrix.val[i])) << i;
    EXPECT_NEAR(r.map.mm_from_px.val[i], s.map.mm_from_px.val[i], 1e-12 * std::abs(s.map.mm_from_px.val[i])) << i;
  }
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(r.camera.distortion[i], s.camera.distortion[i], 1e-12 * std::abs(s.camera.distortion[i]));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.plane[i], s.plane[i], 1e-12 * std::abs(s.plane[i]));
  EXPECT_EQ(r.camera.image_size, s.camera.image_size);
  EXPECT_EQ(r.stripe.axis, StripeAxis::kColumns);
  EXPECT_EQ(r.stripe.method, StripeMethod::kSteger);
  EXPECT_EQ(r.stripe.rule, PeakRule::kNearest);
  EXPECT_EQ(r.stripe.threshold, 180);
  EXPECT_EQ(r.stripe.max_width_px, s.stripe.max_width_px);
}

TEST(SensorYaml, MalformedKeysAreNamed) {
  test::TempDir dir;
  const std::string good =
      "camera:\n"
      "  matrix: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\n"
      "  distortion: [0, 0, 0, 0, 0]\n"
      "  image_size: [640, 480]\n"
      "laser:\n"
      "  plane: [0.8, 0, 0.6, -180]\n"
      "  homography: [[0.1, 0, -32], [0, 0.1, -24], [0, 0, 1]]\n";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::pair<std::string, std::string> cases[] = {
      {with("  distortion: [0, 0, 0, 0, 0]\n", ""), "camera.distortion: missing"},
      {with("[0, 0, 0, 0, 0]", "[0, 0, 0]"), "line 3: camera.distortion: expected a list of 5 numbers"},
      {with("[[800, 0, 320]", "[[-800, 0, 320]"), "line 2: camera.matrix: expected [[fx"},
      {with("[640, 480]", "[640.5, 480]"), "line 4: camera.image_size: expected [width, height], whole pixels"},
      {with("[0.8, 0, 0.6, -180]", "[1, 1, 0, -180]"),
       "line 6: laser.plane: expected [a, b, c, d] with (a, b, c) a unit vector"},
      {with("[0, 0.1, -24]", "[0.2, 0, -64]"), "laser.homography: singular"},
      {with("[0, 0.1, -24], [0, 0, 1]]", "[0, 0.1, -24], [0, 0, .nan]]"),
       "line 7: laser.homography: expected a finite number"},
      {good + "stripe: {axis: diagonal}\n", "stripe.axis: stripe axis 'diagonal': expected one of auto, rows, columns"},
      {good + "stripe: {max_width_px: 0.5}\n", "stripe: stripe options: max_width_px must exceed min_width_px"},
      {good + "stripe: [rows]\n", "stripe: expected a mapping"},
      {"- 1\n- 2\n", "expected a mapping with camera, laser and stripe"},
  };
  int k = 0;
  for (const auto& [text, expect] : cases) {
    const std::string path = dir / ("bad" + std::to_string(k++) + ".yaml");
    test::WriteText(path, text);
    test::ExpectRejected(path, expect, [&] { ReadSensorYaml(path); });
  }
}

}  // namespace
}  // namespace bead::vision
