// `bead frames` end to end: PNG frames of a parabolic bead (24 mm^2) seen
// through a tilted camera, and the laser plane file from nine target
// points, become a run archive that `bead measure` measures as the bead;
// unreadable frames and bad plane files are errors naming the file.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <iomanip>
#include <sstream>

#include "libbead/io/csv_reader.h"
#include "libbead/io/run_archive.h"
#include "tests/support/run_cli.h"
#include "tests/vision/render_stripe.h"

namespace bead {
namespace {

using test::RunCli;

TEST(FramesCommand, PngFramesMeasureAsTheBead) {
  test::TempDir dir;
  std::ostringstream plane;
  plane << "points:  # [u, v, x_mm, z_mm]\n";
  for (double u : {50.0, 600.0, 1200.0})
    for (double v : {20.0, 200.0, 440.0}) {
      const cv::Point2d p = test::Apply(test::kTiltedCamera, {u, v});
      plane << "  - [" << u << ", " << v << ", " << std::setprecision(17) << p.x << ", " << p.y << "]\n";
    }
  test::WriteText(dir / "plane.yaml", plane.str());
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  const test::Stripe stripe{[](int u) { return test::StripeRow(u, test::Parabola12x3); }, 1.6, 180.0, 12.0};
  const cv::Mat frame = test::RenderStripe(470, 1251, stripe, CV_8U);
  std::string frames;
  for (int k = 0; k < 3; ++k) {
    const std::string path = dir / ("frame" + std::to_string(k) + ".png");
    ASSERT_TRUE(cv::imwrite(path, frame));
    frames += " " + path;
  }
  auto [read, read_out] =
      RunCli(dir, "frames --plane " + (dir / "plane.yaml") + " --rate-hz 200" + frames + " -o " + (dir / "run.h5"));
  ASSERT_EQ(read, 0) << read_out;
  EXPECT_NE(read_out.find("3 frames of 1251 lines: 3753 stripe points"), std::string::npos) << read_out;
  const RunArchive run = ReadRunArchive(dir / "run.h5");
  EXPECT_TRUE(EncoderAbsent(run));
  EXPECT_EQ(run.profiles.t_s, (std::vector<double>{0.0, 0.005, 0.010}));

  auto [measured, measure_out] = RunCli(
      dir, "measure --occlusion none --rig " + (dir / "rig.yaml") + " " + (dir / "run.h5") + " -o " + (dir / "g.csv"));
  ASSERT_EQ(measured, 0) << measure_out;
  CsvReader csv(dir / "g.csv");
  csv.Header({"profile", "t_s", "encoder", "area_mm2", "width_mm", "height_mm"}, "geometry CSV");
  int rows = 0;
  while (csv.Next()) {
    ++rows;
    // frame_profile_test.cc's bounds for this frame: H dx + W 0.036 px
    // x 0.015 mm/px for the area, 2 dx (+ the stripe's share) for the width.
    EXPECT_NEAR(csv.Double(3, "area_mm2"), 24.0, 3.0 * 0.04 + 12.0 * 0.036 * 0.015);
    EXPECT_NEAR(csv.Double(4, "width_mm"), 12.0, 2 * 0.04 + 2 * 0.036 * 0.015);
  }
  EXPECT_EQ(rows, 3);
}

TEST(FramesCommand, UnreadableFramesAndBadPlaneFilesNameTheFile) {
  test::TempDir dir;
  test::WriteText(dir / "not-an-image.png", "profile,t_s\n");
  cv::imwrite(dir / "frame.png", cv::Mat(50, 60, CV_8U, cv::Scalar(0)));
  // `bead frames` on one frame with the plane file `plane`.
  auto frames = [&](const std::string& plane, const std::string& frame) {
    test::WriteText(dir / "plane.yaml", plane);
    return RunCli(
        dir, "frames --plane " + (dir / "plane.yaml") + " --rate-hz 10 " + (dir / frame) + " -o " + (dir / "run.h5"));
  };
  const std::string three = "points:\n  - [0, 0, 0, 0]\n  - [100, 0, 4, 0]\n  - [0, 100, 0, -1.5]\n";
  auto [few, few_out] = frames(three, "frame.png");
  EXPECT_EQ(few, 1);
  EXPECT_NE(few_out.find(dir / "plane.yaml"), std::string::npos) << few_out;
  EXPECT_NE(few_out.find("needs 4 or more"), std::string::npos) << few_out;
  auto [bad, bad_out] = frames(three + "  - [100, 100, 4, -1.5]\n  - [50, 50, two, 1]\n", "frame.png");
  EXPECT_EQ(bad, 1);
  EXPECT_NE(bad_out.find(dir / "plane.yaml" + ": line 6: points"), std::string::npos) << bad_out;
  auto [image, image_out] = frames(three + "  - [100, 100, 4, -1.5]\n", "not-an-image.png");
  EXPECT_EQ(image, 1);
  EXPECT_NE(image_out.find(dir / "not-an-image.png" + ": not an image"), std::string::npos) << image_out;
  EXPECT_FALSE(std::filesystem::exists(dir / "run.h5"));
}

}  // namespace
}  // namespace bead
