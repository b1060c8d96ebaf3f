#include "libbead/vision/stripe_steger.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace bead::vision::detail {
namespace {

// Sampled Gaussian-derivative weights on d = -r..r, normalised so that
// the responses are exact for polynomials: sum g = 1, sum d g1 = 1,
// sum g2 = 0 and sum d^2 / 2 g2 = 1 (Steger 1998, sec. 3: the
// derivatives of the image convolved with a Gaussian of scale sigma).
struct Kernels {
  int r = 0;
  std::vector<double> g, g1, g2;
  explicit Kernels(double sigma) : r(static_cast<int>(std::ceil(3.0 * sigma))) {
    const int n = 2 * r + 1;
    g.resize(n), g1.resize(n), g2.resize(n);
    double s0 = 0.0, s1 = 0.0, m2 = 0.0;
    const double s2 = sigma * sigma;
    for (int k = 0; k < n; ++k) {
      const double d = k - r, e = std::exp(-d * d / (2.0 * s2));
      g[k] = e, g1[k] = d / s2 * e, g2[k] = (d * d / (s2 * s2) - 1.0 / s2) * e;
      s0 += g[k], s1 += d * g1[k], m2 += g2[k];
    }
    double q = 0.0;
    for (int k = 0; k < n; ++k) {
      const double d = k - r;
      g[k] /= s0, g1[k] /= s1, g2[k] -= m2 / n;
      q += 0.5 * d * d * g2[k];
    }
    for (double& w : g2) w /= q;
  }
};

template <typename T>
struct Responses {
  double rx = 0, ry = 0, rxx = 0, rxy = 0, ryy = 0;
  Responses(const cv::Mat& im, int x, int y, const Kernels& k) {
    const int cols = im.cols, rows = im.rows;
    for (int dy = -k.r; dy <= k.r; ++dy) {
      const T* row = im.ptr<T>(std::clamp(y + dy, 0, rows - 1));
      double s0 = 0, s1 = 0, s2 = 0;
      for (int dx = -k.r; dx <= k.r; ++dx) {
        const double v = static_cast<double>(row[std::clamp(x + dx, 0, cols - 1)]);
        s0 += v * k.g[dx + k.r], s1 += v * k.g1[dx + k.r], s2 += v * k.g2[dx + k.r];
      }
      const double wy = k.g[dy + k.r], wy1 = k.g1[dy + k.r], wy2 = k.g2[dy + k.r];
      rx += s1 * wy, rxx += s2 * wy, ry += s0 * wy1, ryy += s0 * wy2, rxy += s1 * wy1;
    }
  }
};

// The centre along the searched line: where the derivative of the line's
// profile smoothed at scale sigma vanishes, x - r_x / r_xx from the
// nearest pixel (Steger 1998, sec. 2, eq. 5 with the Taylor step of
// sec. 3). Along the line rather than along the 2-D normal: smoothing a
// curved stripe in 2-D moves its ridge toward the centre of curvature by
// about sigma^2 k / 2 (0.5 px for a wide stripe curving at 0.04 / px),
// while the line's own profile of a straight or tilted stripe stays
// symmetric about the crossing.
template <typename T>
bool CentreAlongLine(const cv::Mat& im, int x, int y, const Kernels& k, double& centre) {
  const T* row = im.ptr<T>(y);
  for (int step = 0; step < 4; ++step) {
    double rx = 0, rxx = 0;
    for (int dx = -k.r; dx <= k.r; ++dx) {
      const double v = static_cast<double>(row[std::clamp(x + dx, 0, im.cols - 1)]);
      rx += v * k.g1[dx + k.r], rxx += v * k.g2[dx + k.r];
    }
    if (!(rxx < 0.0)) return false;
    const double c = x - rx / rxx;
    // Within the pixel (a little beyond its half, so that a centre on a
    // pixel boundary, seen from either side, is not chased back and forth).
    if (std::abs(c - x) <= 0.6) {
      centre = c;
      return true;
    }
    x += c > x ? 1 : -1;
    if (x < 0 || x >= im.cols) return false;
  }
  return false;
}

template <typename T>
bool Centre(const cv::Mat& im, int x, int y, double sigma, double& centre) {
  const Kernels k(sigma);
  if (y >= k.r && y + k.r < im.rows) {
    // The Hessian at the peak: its most negative eigenvalue must dominate
    // (a bright line, not a blob or an edge), and its eigenvector, the
    // line's normal, must not lie across the searched line (the stripe
    // would run along it).
    const Responses<T> r(im, x, y, k);
    const double mean = 0.5 * (r.rxx + r.ryy), dev = std::hypot(0.5 * (r.rxx - r.ryy), r.rxy);
    const double lambda = mean - dev, other = mean + dev;
    if (!(lambda < 0.0) || std::abs(lambda) <= std::abs(other)) return false;
    // (H - lambda) n = 0 from either row; the longer of the two is the
    // better conditioned (the other vanishes when n lies along an axis).
    double nx = r.rxy, ny = lambda - r.rxx;
    if (std::hypot(lambda - r.ryy, r.rxy) > std::hypot(nx, ny)) nx = lambda - r.ryy, ny = r.rxy;
    const double norm = std::hypot(nx, ny);
    if (norm > 0.0 && std::abs(nx) / norm < 0.2) return false;
  }
  return CentreAlongLine<T>(im, x, y, k, centre);
}

}  // namespace

bool StegerCentre(const cv::Mat& lines, int x, int y, double sigma_px, double& centre) {
  switch (lines.depth()) {
    case CV_8U:
      return Centre<std::uint8_t>(lines, x, y, sigma_px, centre);
    case CV_16U:
      return Centre<std::uint16_t>(lines, x, y, sigma_px, centre);
    case CV_32F:
      return Centre<float>(lines, x, y, sigma_px, centre);
    default:
      return false;
  }
}

}  // namespace bead::vision::detail
