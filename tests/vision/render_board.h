// Frames of a chessboard lying on a plate, lit by a laser sheet, seen by
// a camera with a known lens: the truth for `bead calibrate laser`.
// Each pixel is the mean of 3 x 3 sub-pixel rays (undistorted with the
// camera's model and met with the board's plane): black and white squares
// on white paper that reaches margin_mm past the squares, a dark table
// beyond; the stripe adds peak exp(-s^2 / (2 width^2)) where s is the
// point's distance from the laser plane, so its centre line is exactly
// where the board meets the plane.
#pragma once

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace bead::test {

struct BoardScene {
  cv::Matx33d camera{800.0, 0.0, 322.0, 0.0, 805.0, 236.0, 0.0, 0.0, 1.0};
  std::array<double, 5> distortion{-0.12, 0.0, 0.0005, -0.0004, 0.0};
  cv::Size size{640, 480};
  int squares_x = 8, squares_y = 7;
  double square_mm = 10.0, margin_mm = 40.0;
  // The laser sheet, camera coordinates: a x + b y + c z + d = 0.
  cv::Vec4d laser{0.8, 0.0, 0.6, -132.0};
  double stripe_width_mm = 0.35, stripe_peak = 170.0;
  double white = 75.0, black = 12.0, table = 6.0;
  // The table beyond the paper lies this far below the board (a plate's
  // thickness), and the stripe falls on it too (0: the table is dark).
  double table_drop_mm = 0.0;
};

// The board's pose: rotation vector and translation, board -> camera, mm.
inline cv::Mat RenderBoard(const BoardScene& s, const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  const int sub = 3;
  std::vector<cv::Point2d> px;
  px.reserve(static_cast<std::size_t>(s.size.area() * sub * sub));
  for (int v = 0; v < s.size.height; ++v)
    for (int u = 0; u < s.size.width; ++u)
      for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) px.emplace_back(u + (i + 0.5) / sub - 0.5, v + (j + 0.5) / sub - 0.5);
  std::vector<cv::Point2d> rays;
  cv::undistortPoints(px, rays, s.camera, s.distortion, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-12));
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  const cv::Vec3d n(r(0, 2), r(1, 2), r(2, 2));
  const cv::Vec3d laser_n(s.laser[0], s.laser[1], s.laser[2]);
  const double x_lo = -s.square_mm, x_hi = (s.squares_x - 1) * s.square_mm;
  const double y_lo = -s.square_mm, y_hi = (s.squares_y - 1) * s.square_mm;
  cv::Mat out(s.size, CV_8UC1);
  std::size_t k = 0;
  for (int v = 0; v < s.size.height; ++v)
    for (int u = 0; u < s.size.width; ++u) {
      double sum = 0.0;
      for (int q = 0; q < sub * sub; ++q, ++k) {
        const cv::Vec3d ray(rays[k].x, rays[k].y, 1.0);
        const cv::Vec3d p = n.dot(tvec) / n.dot(ray) * ray;
        const cv::Vec3d b = r.t() * (p - tvec);
        double level = s.table;
        const bool paper = b[0] > x_lo - s.margin_mm && b[0] < x_hi + s.margin_mm && b[1] > y_lo - s.margin_mm &&
                           b[1] < y_hi + s.margin_mm;
        if (!paper && s.table_drop_mm > 0.0) {
          // Away from the camera (which sits at the origin) by the drop.
          const double away = n.dot(tvec) > 0.0 ? s.table_drop_mm : -s.table_drop_mm;
          const cv::Vec3d q = (n.dot(tvec) + away) / n.dot(ray) * ray;
          const double dist = laser_n.dot(q) + s.laser[3];
          level += s.stripe_peak * std::exp(-dist * dist / (2.0 * s.stripe_width_mm * s.stripe_width_mm));
        }
        if (paper) {
          level = s.white;
          if (b[0] > x_lo && b[0] < x_hi && b[1] > y_lo && b[1] < y_hi) {
            const int parity = static_cast<int>(std::floor(b[0] / s.square_mm) + std::floor(b[1] / s.square_mm));
            if ((parity & 1) == 0) level = s.black;
          }
          const double dist = laser_n.dot(p) + s.laser[3];
          level += s.stripe_peak * std::exp(-dist * dist / (2.0 * s.stripe_width_mm * s.stripe_width_mm));
        }
        sum += level;
      }
      out.at<unsigned char>(v, u) = cv::saturate_cast<unsigned char>(sum / (sub * sub));
    }
  return out;
}

}  // namespace bead::test
