// Real frames of another group's sheet-of-light head (testdata/realdata/
// etna, BSD): the stripe runs down the image over a chessboard. The stripe
// found must be the stripe, never a square; the camera and the laser plane
// calibrate from the eight frames; the frames then become profiles.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <regex>

#include <opencv2/imgproc.hpp>

#include "calibration/chessboard.h"
#include "libbead/io/run_archive.h"
#include "libbead/vision/sensor_yaml.h"
#include "libbead/vision/stripe.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

const std::string kDir = std::string(BEAD_SOURCE_DIR) + "/testdata/realdata/etna/";

std::string Frames() {
  std::string out;
  for (int k = 1; k <= 8; ++k) out += " " + kDir + "frame000" + std::to_string(k) + ".png";
  return out;
}

// Frame 3 (stripe on the paper beside the board) and frame 6 (across the
// squares' corner): searched along the columns (one centre per row) the
// stripe is found on nearly every row and its centres lie on a straight
// line (the paper is flat, the lens nearly straight there). Searched the
// wrong way (one centre per column, what the first round did, when it
// reported 77 % of the columns as stripe, all of them squares or
// background), nothing is found inside the board's squares unless on the
// stripe's line: frame 3's steep stripe is too wide along a column and
// nothing else is taken for it; in frame 6 the stripe and real bright
// lines off the board (a scrap of paper's glare, the stripe's kink onto
// another surface) are found.
TEST(EtnaFrames, TheStripeIsTheStripeNeverASquare) {
  const calibration::Board board{8, 7, 10.0};
  for (const char* name : {"frame0003.png", "frame0006.png"}) {
    const cv::Mat frame = cv::imread(kDir + name, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(frame.type(), CV_8UC1) << name;
    vision::StripeCentres down, across;
    vision::FindStripe(frame, {}, down);
    EXPECT_EQ(down.axis, vision::StripeAxis::kColumns) << name;
    EXPECT_GT(down.stats.found, 0.9 * frame.rows) << name << ": " << vision::Describe(down.stats);
    // The line u = a + b v through the rows' centres, by least squares
    // over the middle half of the rows (the far ends may leave the paper).
    double n = 0, sv = 0, su = 0, svv = 0, suv = 0;
    for (int v = frame.rows / 4; v < 3 * frame.rows / 4; ++v) {
      const double u = down.centres[static_cast<std::size_t>(v)];
      if (std::isnan(u)) continue;
      n += 1, sv += v, su += u, svv += double(v) * v, suv += u * v;
    }
    const double b = (n * suv - sv * su) / (n * svv - sv * sv), a = (su - b * sv) / n;
    int off = 0;
    for (int v = frame.rows / 4; v < 3 * frame.rows / 4; ++v) {
      const double u = down.centres[static_cast<std::size_t>(v)];
      off += !std::isnan(u) && std::abs(u - (a + b * v)) > 3.0;
    }
    EXPECT_LT(off, 0.02 * n) << name << ": rows whose centre is off the line by more than 3 px";

    // The squares: the hull of the inner corners, grown by one square.
    const std::vector<cv::Point2f> corners = calibration::FindBoard(frame, board);
    ASSERT_EQ(corners.size(), 42u) << name;
    std::vector<cv::Point2f> hull;
    cv::convexHull(corners, hull);
    const double square_px = cv::norm(corners[1] - corners[0]);
    vision::StripeOptions wrong;
    wrong.axis = vision::StripeAxis::kRows;
    vision::FindStripe(frame, wrong, across);
    int on_squares = 0;
    for (int u = 0; u < frame.cols; ++u) {
      const double v = across.centres[static_cast<std::size_t>(u)];
      if (std::isnan(v)) continue;
      const bool on_line = std::abs(u - (a + b * v)) < 3.0 * std::max(1.0, std::abs(b));
      const bool in_board =
          cv::pointPolygonTest(hull, cv::Point2f(static_cast<float>(u), static_cast<float>(v)), true) > -square_px;
      on_squares += in_board && !on_line;
    }
    // Frame 6's stripe jogs by 10 to 60 px where it crosses the board's
    // last black square (it is the stripe, off its straight line there):
    // a dozen columns. The first round took 77 % of all columns.
    EXPECT_LE(on_squares, 15) << name << ": " << vision::Describe(across.stats);
  }
}

// The camera: the authors' README finds fx about 2400 px by OpenCV on
// these frames; 8 views of a 7 x 6 board put its standard deviation near
// 1 % (the command prints it). The corners to a fraction of a pixel.
TEST(EtnaFrames, CalibrateLaserAndMapTheFrames) {
  test::TempDir dir;
  auto [status, out] =
      test::RunCli(dir, "calibrate laser --board 8x7 --square-mm 10" + Frames() + " -o " + (dir / "sensor.yaml"));
  ASSERT_EQ(status, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      out, m, std::regex(R"(reprojection_rms_px=([0-9.]+) plane_rms_mm=([0-9.]+) images_used=(\d+)/8)")))
      << out;
  EXPECT_LT(std::stod(m[1]), 1.0) << out;
  EXPECT_GE(std::stoi(m[3]), 6) << out;
  EXPECT_NE(out.find("frame0008.png   yes"), std::string::npos) << out;
  const vision::SensorModel sensor = vision::ReadSensorYaml(dir / "sensor.yaml");
  EXPECT_NEAR(sensor.camera.matrix(0, 0), 2400.0, 150.0);
  EXPECT_EQ(sensor.camera.image_size, cv::Size(1280, 1024));
  EXPECT_EQ(sensor.stripe.axis, vision::StripeAxis::kColumns);

  auto [framed, frames_out] = test::RunCli(dir, "frames --sensor " + (dir / "sensor.yaml") + " --rate-hz 10 " + kDir +
                                                    "frame0005.png " + kDir + "frame0007.png -o " + (dir / "run.h5"));
  ASSERT_EQ(framed, 0) << frames_out;
  EXPECT_NE(frames_out.find("stripe: axis columns (one point per row)"), std::string::npos) << frames_out;
  const RunArchive run = ReadRunArchive(dir / "run.h5");
  ASSERT_EQ(run.profiles.points, 1024u);
  // Frame 5's stripe lies on the flat board: its profile is a straight
  // line in (x, z), within the plane fit's spread of it.
  double n = 0, sx = 0, sz = 0, sxx = 0, sxz = 0;
  for (std::size_t k = 0; k < 1024; ++k) {
    const double x = run.profiles.x_mm[k], z = run.profiles.z_mm[k];
    if (std::isnan(x)) continue;
    n += 1, sx += x, sz += z, sxx += x * x, sxz += x * z;
  }
  ASSERT_GT(n, 900);
  const double slope = (n * sxz - sx * sz) / (n * sxx - sx * sx), icept = (sz - slope * sx) / n;
  double ss = 0;
  for (std::size_t k = 0; k < 1024; ++k) {
    const double x = run.profiles.x_mm[k], z = run.profiles.z_mm[k];
    if (!std::isnan(x)) ss += (z - icept - slope * x) * (z - icept - slope * x);
  }
  EXPECT_LT(std::sqrt(ss / n), 3.0 * std::stod(m[2])) << frames_out;
}

TEST(EtnaFrames, BadBoardsAndImagesAreNamed) {
  test::TempDir dir;
  auto [square, square_out] = test::RunCli(dir, "calibrate laser --board 8x8 --square-mm 10" + Frames());
  EXPECT_EQ(square, 1);
  EXPECT_NE(square_out.find("no unique order"), std::string::npos) << square_out;
  test::WriteText(dir / "not.png", "not an image");
  auto [bad, bad_out] = test::RunCli(dir, "calibrate laser --board 8x7 --square-mm 10 " + (dir / "not.png"));
  EXPECT_EQ(bad, 1);
  EXPECT_NE(bad_out.find("not.png: not an image OpenCV can read"), std::string::npos) << bad_out;
  // A board the frames do not show (9 x 7 squares); two frames (a failed
  // search tries four ways: half and full size, with the stripe and
  // without).
  auto [wrong, wrong_out] = test::RunCli(
      dir, "calibrate laser --board 9x7 --square-mm 10 " + kDir + "frame0001.png " + kDir + "frame0002.png");
  EXPECT_EQ(wrong, 1);
  EXPECT_NE(wrong_out.find("found in 0 image(s)"), std::string::npos) << wrong_out;
}

}  // namespace
}  // namespace bead
