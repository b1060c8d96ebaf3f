#include "libbead/profile/reference_line.h"

#include <cmath>
#include <cstddef>

#include "libbead/profile/gather.h"
#include "libbead/profile/median.h"

namespace bead {
namespace {

// The MAD of a normal distribution times this is its standard deviation.
constexpr double kMadToSigma = 1.482602218505602;

std::size_t StrideFor(std::size_t n, int max_samples) {
  const std::size_t m = static_cast<std::size_t>(max_samples < 1 ? 1 : max_samples);
  return n <= m ? 1 : (n + m - 1) / m;
}

// Median of every `stride`-th of the first n values, via `scratch`.
double StridedMedian(const std::vector<double>& values, std::size_t n, std::size_t stride, std::vector<double>& scratch) {
  scratch.clear();
  for (std::size_t i = stride / 2; i < n; i += stride) scratch.push_back(values[i]);
  return MedianInPlace(scratch.data(), scratch.size());
}

// The points of both areas, each area strided for the robust statistics.
struct AreaPoints {
  const ProfileWorkspace& w;
  std::size_t stride_l, stride_r;
};

// Vertical inlier band about z = a + b x: `inlier_sigmas` robust standard
// deviations (1.4826 MAD) of the strided samples' residuals, never below
// the floor `min_sigma_mm`.
double InlierBand(const AreaPoints& p, std::vector<double>& scratch, double a, double b,
                  const ReferenceLineOptions& options) {
  const ProfileWorkspace& w = p.w;
  scratch.clear();
  for (std::size_t i = p.stride_l / 2; i < w.n_left; i += p.stride_l)
    scratch.push_back(std::abs(w.left_z[i] - a - b * w.left_x[i]));
  for (std::size_t i = p.stride_r / 2; i < w.n_right; i += p.stride_r)
    scratch.push_back(std::abs(w.right_z[i] - a - b * w.right_x[i]));
  const double sigma_v = std::max(kMadToSigma * MedianInPlace(scratch.data(), scratch.size()),
                                  options.min_sigma_mm * std::sqrt(1.0 + b * b));
  return options.inlier_sigmas * sigma_v;
}

// Least-squares sums of the inliers, shifted by (x0, z0) for conditioning.
struct Sums {
  double n = 0, sx = 0, sz = 0, sxx = 0, sxz = 0, rr = 0;
  int Add(const std::vector<double>& xs, const std::vector<double>& zs, std::size_t count, double a, double b,
          double band, double x0, double z0) {
    int used = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const double r = zs[i] - a - b * xs[i];
      if (std::abs(r) > band) continue;
      const double dx = xs[i] - x0;
      const double dz = zs[i] - z0;
      n += 1;
      sx += dx;
      sz += dz;
      sxx += dx * dx;
      sxz += dx * dz;
      rr += r * r;
      ++used;
    }
    return used;
  }
};

}  // namespace

double ReferenceLine::HeightAt(double x_mm, double z_mm) const {
  return (z_mm - intercept_mm - slope * x_mm) / std::sqrt(1.0 + slope * slope);
}

ReferenceLine FitReferenceLine(const ProfileView& view, const ReferenceArea& left,
                               const ReferenceArea& right, const ReferenceLineOptions& options,
                               ProfileWorkspace& w) {
  GatherPoints(view, left, right, w);
  return FitGatheredReferenceLine(options, w);
}

ReferenceLine FitGatheredReferenceLine(const ReferenceLineOptions& options, ProfileWorkspace& w) {
  ReferenceLine line;
  line.points_available = static_cast<int>(w.n_left + w.n_right);
  const auto min_points = static_cast<std::size_t>(options.min_points_per_area);
  if (w.n_left < min_points || w.n_right < min_points) return line;

  // Robust start: the line through each area's (median x, median z).
  const AreaPoints points{w, StrideFor(w.n_left, options.max_median_samples),
                          StrideFor(w.n_right, options.max_median_samples)};
  const double xl = StridedMedian(w.left_x, w.n_left, points.stride_l, w.scratch);
  const double zl = StridedMedian(w.left_z, w.n_left, points.stride_l, w.scratch);
  const double xr = StridedMedian(w.right_x, w.n_right, points.stride_r, w.scratch);
  const double zr = StridedMedian(w.right_z, w.n_right, points.stride_r, w.scratch);
  double b = (zr - zl) / (xr - xl);
  double a = zl - b * xl;

  // Refits on the inliers; the last pass only measures the final line.
  for (int iter = 0; iter <= options.iterations; ++iter) {
    const double band = InlierBand(points, w.scratch, a, b, options);
    Sums sums;
    const int used_l = sums.Add(w.left_x, w.left_z, w.n_left, a, b, band, xl, zl);
    const int used_r = sums.Add(w.right_x, w.right_z, w.n_right, a, b, band, xl, zl);
    if (used_l < options.min_points_per_area || used_r < options.min_points_per_area) return line;
    if (iter == options.iterations) {
      line.ok = true;
      line.intercept_mm = a;
      line.slope = b;
      line.points_used = used_l + used_r;
      line.residual_rms_mm = std::sqrt(sums.rr / sums.n / (1.0 + b * b));
      return line;
    }
    const double mx = sums.sx / sums.n;
    const double mz = sums.sz / sums.n;
    const double sxx = sums.sxx - sums.n * mx * mx;
    if (!(sxx > 0.0)) return line;
    b = (sums.sxz - sums.n * mx * mz) / sxx;
    a = (zl + mz) - b * (xl + mx);
  }
  return line;
}

}  // namespace bead
