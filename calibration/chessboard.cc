#include "calibration/chessboard.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>

#include "libbead/core/error.h"

namespace bead::calibration {

std::vector<cv::Point3f> Board::Corners() const {
  std::vector<cv::Point3f> out;
  const cv::Size inner = InnerCorners();
  for (int y = 0; y < inner.height; ++y)
    for (int x = 0; x < inner.width; ++x)
      out.emplace_back(static_cast<float>(x * square_mm), static_cast<float>(y * square_mm), 0.0f);
  return out;
}

Board ParseBoard(const std::string& text, double square_mm) {
  Board b;
  int used = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &b.squares_x, &b.squares_y, &used) != 2 ||
      used != static_cast<int>(text.size()))
    throw Error("--board '" + text + "': expected COLSxROWS, the squares along each side as printed (e.g. 8x7)");
  if (b.squares_x < 3 || b.squares_y < 3 || b.squares_x > 100 || b.squares_y > 100)
    throw Error("--board '" + text + "': each side needs 3 to 100 squares (2 or more inner corners)");
  if (b.squares_x == b.squares_y)
    throw Error("--board '" + text +
                "': a square board's corners have no unique order; use a board with an "
                "odd and an even side (e.g. 8x7)");
  if (!(square_mm > 0.0) || !std::isfinite(square_mm)) throw Error("--square-mm: must be a positive length, mm");
  b.square_mm = square_mm;
  return b;
}

namespace {

// The board's inner corners in `image` (grey), at half size first: the
// corners in full-size pixels, or empty.
std::vector<cv::Point2f> Detect(const cv::Mat& image, const Board& board) {
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  std::vector<cv::Point2f> corners;
  cv::Mat half;
  cv::resize(image, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  if (cv::findChessboardCorners(half, board.InnerCorners(), corners, flags)) {
    // A half-size pixel i covers full-size pixels 2i and 2i + 1: its
    // centre is at 2i + 0.5.
    for (cv::Point2f& p : corners) p = p * 2.0f + cv::Point2f(0.5f, 0.5f);
    return corners;
  }
  if (cv::findChessboardCorners(image, board.InnerCorners(), corners, flags)) return corners;
  return {};
}

}  // namespace

std::vector<cv::Point2f> FindBoard(const cv::Mat& grey, const Board& board) {
  cv::Mat eight = grey;
  if (grey.depth() != CV_8U) cv::normalize(grey, eight, 0, 255, cv::NORM_MINMAX, CV_8U);
  cv::Mat image = eight;  // shares the frame's pixels: never written into
  std::vector<cv::Point2f> corners = Detect(image, board);
  if (corners.empty()) {
    // The stripe across the squares breaks the search: a grey opening
    // (erosion, then dilation) 9 px wide removes bright lines narrower
    // than that and keeps the squares, whose quadrants at a corner are
    // convex and wider: their corners stay where they were, so they are
    // refined on the opened image too (the stripe would pull them).
    cv::Mat opened;
    cv::morphologyEx(eight, opened, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(9, 9)));
    image = opened;
    corners = Detect(image, board);
  }
  if (corners.empty()) return {};
  // The refinement window: a third of the smallest corner spacing seen.
  double spacing = 1e9;
  const cv::Size inner = board.InnerCorners();
  for (int y = 0; y < inner.height; ++y)
    for (int x = 0; x + 1 < inner.width; ++x)
      spacing = std::min(spacing, cv::norm(corners[y * inner.width + x + 1] - corners[y * inner.width + x]));
  const int win = std::clamp(static_cast<int>(spacing / 3.0), 2, 15);
  cv::cornerSubPix(image, corners, cv::Size(win, win), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  return corners;
}

LensTerms ParseLensTerms(const std::string& text) {
  if (text == "k1") return LensTerms::kK1;
  if (text == "k1k2") return LensTerms::kK1K2;
  if (text == "k1k2p") return LensTerms::kK1K2P;
  if (text == "full") return LensTerms::kFull;
  throw Error("--lens '" + text + "': expected k1, k1k2, k1k2p (k1 k2 and tangential p1 p2) or full (k1 k2 p1 p2 k3)");
}

CameraFit FitCamera(const Board& board, const std::vector<std::vector<cv::Point2f>>& views, cv::Size image_size,
                    LensTerms lens) {
  if (views.size() < 3)
    throw Error("the board was found in " + std::to_string(views.size()) +
                " image(s); a camera needs 3 or more views of it, at different tilts");
  const std::vector<std::vector<cv::Point3f>> object(views.size(), board.Corners());
  cv::Mat k, d, sd_intrinsics, sd_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  int flags = 0;
  switch (lens) {
    case LensTerms::kK1:
      flags = cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
      break;
    case LensTerms::kK1K2:
      flags = cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
      break;
    case LensTerms::kK1K2P:
      flags = cv::CALIB_FIX_K3;
      break;
    case LensTerms::kFull:
      break;
  }
  CameraFit fit;
  fit.rms_px =
      cv::calibrateCamera(object, views, image_size, k, d, rvecs, tvecs, sd_intrinsics, sd_extrinsics, per_view, flags,
                          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  fit.camera.matrix = cv::Matx33d(k);
  for (int i = 0; i < 5; ++i) fit.camera.distortion[static_cast<std::size_t>(i)] = d.at<double>(i);
  fit.camera.image_size = image_size;
  for (int i = 0; i < per_view.rows; ++i) fit.view_rms_px.push_back(per_view.at<double>(i));
  for (std::size_t i = 0; i < rvecs.size(); ++i) fit.rvecs.emplace_back(rvecs[i]), fit.tvecs.emplace_back(tvecs[i]);
  for (int i = 0; i < 9; ++i) fit.sd[static_cast<std::size_t>(i)] = sd_intrinsics.at<double>(i);
  return fit;
}

}  // namespace bead::calibration
