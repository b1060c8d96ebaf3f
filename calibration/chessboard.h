// A printed chessboard in a camera frame: its inner corners, to a fraction
// of a pixel, and the camera's intrinsics and lens distortion from several
// views of it (Zhang, "A flexible new technique for camera calibration",
// IEEE PAMI 22(11), 2000, as OpenCV's calib3d implements it).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "libbead/vision/sensor.h"

namespace bead::calibration {

struct Board {
  int squares_x = 0, squares_y = 0;  // as printed: squares along each side
  double square_mm = 0.0;
  cv::Size InnerCorners() const { return {squares_x - 1, squares_y - 1}; }
  // The inner corners on the board's plane (z = 0), mm, in OpenCV's order.
  std::vector<cv::Point3f> Corners() const;
};

// "COLSxROWS" (squares) -> a board; throws bead::Error naming what is wrong.
Board ParseBoard(const std::string& text, double square_mm);

// The board's inner corners in a grey frame, refined to sub-pixel; empty
// when the board is not found. Tries the frame at half size first (a
// stripe crossing the board breaks the full-size search more often), then
// at full size.
std::vector<cv::Point2f> FindBoard(const cv::Mat& grey, const Board& board);

struct CameraFit {
  vision::CameraModel camera;
  double rms_px = 0.0;                  // over all corners of all views
  std::vector<double> view_rms_px;      // per view
  std::vector<cv::Vec3d> rvecs, tvecs;  // board -> camera, per view (mm)
  // One standard deviation of fx, fy, cx, cy (px) and k1, k2, p1, p2, k3
  // from the fit's covariance (OpenCV's stdDeviationsIntrinsics).
  std::array<double, 9> sd{};
};

// Which distortion terms are fitted; the others are held at 0. A
// handful of views determines the higher terms poorly (their standard
// deviations say how poorly).
enum class LensTerms { kK1, kK1K2, kK1K2P, kFull };  // full: k1 k2 p1 p2 k3
LensTerms ParseLensTerms(const std::string& text);   // "k1", "k1k2", "k1k2p", "full"

// Views: each view's corners (FindBoard).
CameraFit FitCamera(const Board& board, const std::vector<std::vector<cv::Point2f>>& views, cv::Size image_size,
                    LensTerms lens);

}  // namespace bead::calibration
