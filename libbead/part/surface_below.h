// The surface a part's bead was laid on (format 1.1): the scan of the layer
// below at the same place along the toolpath, in the bed frame (x_bed =
// x + frame_x_mm, z_bed = z + frame_z_mm). A layer's profiles are kept as
// they are measured; when the next layer begins they become the surface
// below and the layer before is let go: memory bounded by one layer, not
// by the part.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bead::part {

// A surface sampled on a uniform x grid (bed frame), NaN where unknown.
// `variance`: each grid value's noise variance over one measured point's
// (1 at a measured point, 1/2 midway between two, less again between two
// profiles), for weighing a difference against it; empty: 0 (a fitted line).
struct SurfaceGrid {
  double x0_mm = 0.0, dx_mm = 0.0;
  std::vector<float> z_mm;
  std::vector<float> variance;
  double VarianceAt(double x_mm) const {
    if (variance.size() != z_mm.size() || z_mm.size() < 2) return 0.0;
    const double u = std::clamp((x_mm - x0_mm) / dx_mm, 0.0, static_cast<double>(z_mm.size() - 1));
    const std::size_t k = std::min(static_cast<std::size_t>(u), z_mm.size() - 2);
    const double t = u - static_cast<double>(k);
    return variance[k] + t * (variance[k + 1] - variance[k]);
  }
  static double NaN() { return std::numeric_limits<double>::quiet_NaN(); }
  // Linear between grid points; NaN outside the grid or next to a NaN.
  double At(double x_mm) const {
    const double u = (x_mm - x0_mm) / dx_mm;
    if (!(u >= 0.0) || !(u <= static_cast<double>(z_mm.size()) - 1.0) || z_mm.size() < 2) return NaN();
    const std::size_t k = std::min(static_cast<std::size_t>(u), z_mm.size() - 2);
    const double t = u - static_cast<double>(k);
    return z_mm[k] + t * (z_mm[k + 1] - z_mm[k]);
  }
  // At and VarianceAt in one lookup, with dz/dx from the two grid points
  // around x (z and slope NaN as At; the variance 0 where the grid
  // carries none).
  struct Sample {
    double z, variance, slope;
  };
  Sample SampleAt(double x_mm) const {
    const double u = (x_mm - x0_mm) / dx_mm;
    if (!(u >= 0.0) || !(u <= static_cast<double>(z_mm.size()) - 1.0) || z_mm.size() < 2) return {NaN(), 0.0, NaN()};
    const std::size_t k = std::min(static_cast<std::size_t>(u), z_mm.size() - 2);
    const double t = u - static_cast<double>(k), rise = static_cast<double>(z_mm[k + 1]) - z_mm[k];
    const double v = variance.size() == z_mm.size() ? variance[k] + t * (variance[k + 1] - variance[k]) : 0.0;
    return {z_mm[k] + t * rise, v, rise / dx_mm};
  }
};

// The points of a grid from x0 to x1 at dx; 0 when it would hold more than
// kMaxGridPoints (a profile whose x spans metres at micrometre spacing is
// no bead's: refused, not allocated).
inline constexpr std::size_t kMaxGridPoints = std::size_t{1} << 22;
inline std::size_t GridPoints(double x0, double x1, double dx) {
  const double n = (x1 - x0) / dx + 2.0;
  return n > 0 && n < static_cast<double>(kMaxGridPoints) ? static_cast<std::size_t>(n) : 0;
}

// One profile of a layer as the next layer's surface: its valid points in
// the bed frame, increasing in x, and its bead's centre (NaN: not found).
struct StoredProfile {
  double path_mm = 0.0;
  double center_x_mm = std::numeric_limits<double>::quiet_NaN();
  double spacing_mm = 0.05;  // the points' median spacing (part/added_bead.h PointSpacingMm)
  std::vector<float> x_mm, z_mm;
};

struct SurfaceBelowOptions {
  // The layer below is not known at a place farther than this from its
  // nearest profile (a stretch not scanned), mm along the path.
  double max_path_gap_mm = 5.0;
  // A gap between a stored profile's valid points longer than this is
  // not bridged (the surface there is unknown), mm.
  double max_x_gap_mm = 1.0;
};

class SurfaceBelow {
 public:
  explicit SurfaceBelow(SurfaceBelowOptions options = {}) : options_(options) {}

  // The layer of the profiles that follow. Layer n + 1 after layer n makes
  // layer n the surface below; a layer skipped leaves none.
  void BeginLayer(int64_t layer);
  int64_t layer() const { return layer_; }
  // Adds a measured profile of the current layer (for the next one).
  void Keep(StoredProfile profile) { current_.push_back(std::move(profile)); }

  // The layer below at `path_mm`, interpolated between its two nearest
  // profiles, on a grid of spacing dx_mm (fine against the points'
  // spacing: an interpolation of the grid is then that of the points),
  // with its variance; nullopt, with `why`, where the
  // layer below is unknown.
  std::optional<SurfaceGrid> At(double path_mm, double dx_mm, std::string* why) const;
  // The bead centre of the layer below at `path_mm` (its own frame).
  double CenterAt(double path_mm) const;

 private:
  // The two stored profiles around `path_mm` and the weight of the second.
  bool Neighbours(double path_mm, std::size_t& i, std::size_t& j, double& w, std::string* why) const;

  SurfaceBelowOptions options_;
  int64_t layer_ = -1;
  bool below_known_ = false;
  std::vector<StoredProfile> below_, current_;
  // At's scratch: the second profile on the grid (a SurfaceBelow serves one thread).
  mutable std::vector<float> za_, va_;
};

}  // namespace bead::part
