// SensorRows: the layer below as a sensor's own rows, for a part's profiles
// measured as they arrive (part/part_profile_processor.h). A profiler's
// points lie on one uniform grid, profile after profile and layer after
// layer (its pixels); each profile of a layer is kept as its z in the bed
// frame and where its grid starts (bed frame x), nothing else: the next
// layer reads two of them around its place along the path straight from
// the store (part/part_kernel.h GridRows: two unaligned loads and a blend a
// row, eight points a register), with no row made, resampled or blended
// first. SurfaceBelow (part/surface_below.h) is the general store, for
// points on no common grid; both keep a layer or two, not the part.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "libbead/part/surface_below.h"

namespace bead::part {

// Where x lies on a uniform grid x0 + k dx (every point within a hundredth
// of dx of its place, dx > 0, at least two points): true and x0, dx.
bool UniformGrid(std::span<const float> x, double& x0, double& dx);

class SensorRows {
 public:
  explicit SensorRows(SurfaceBelowOptions options = {}) : options_(options) {}

  // The layer of the profiles that follow (as SurfaceBelow::BeginLayer).
  void BeginLayer(int64_t layer);
  int64_t layer() const { return layer_; }
  // The grid's spacing (0 before the first profile): every row has it.
  double dx() const { return dx_; }
  // Keeps a profile of the current layer: z + frame_z on the grid from
  // x0_bed_mm at dx (dx() must be 0 or dx). Its values, valid until the
  // next Keep.
  const float* Keep(double path_mm, double x0_bed_mm, double dx, std::span<const float> z, double frame_z);

  struct Row {
    double path_mm = 0.0, x0_mm = 0.0;
    std::vector<float> z;
  };
  // The layer below's two rows around `path_mm` (the same row twice at an
  // end) and the second's weight, as SurfaceBelow::At chooses them; false,
  // with `why`, where the layer below is not known there.
  struct Pair {
    const float* z[2] = {};
    double x0_mm[2] = {};
    std::size_t size[2] = {};
    double w = 0.0;
    int count = 0;
  };
  bool At(double path_mm, Pair& out, std::string* why) const;

  // The rows kept, for the general store to take over (part_profile_processor.cc).
  bool below_known() const { return below_known_; }
  std::span<const Row> below_rows() const { return below_; }
  std::span<const Row> current_rows() const { return current_; }

 private:
  SurfaceBelowOptions options_;
  int64_t layer_ = -1;
  bool below_known_ = false;
  double dx_ = 0.0;
  std::vector<Row> below_, current_;
  // The values of rows let go (the layer before the one below), refilled
  // by the next profiles: after the first layers nothing is allocated.
  std::vector<std::vector<float>> spare_;
  // The last place read (At: the direction the head moves).
  mutable double last_path_ = 0.0;
};

}  // namespace bead::part
