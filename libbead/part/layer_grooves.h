// The groove a layer's beads hide under their overhangs (part/hidden_groove.h),
// taken off each row's area. One material, one process: the layer's first
// rows, each bead's shape its own (placed at its silhouette, or fitted),
// pool its beads' aspect b / a and exponent (part/superellipse.h), and every
// row of the layer is corrected with the shape held, the first ones too.
// One profile alone, where the
// bead's sides are seen poorly, can misplace its widest point (on the
// twin's contour, fitted from eight starts, one in ten of a layer's first
// rows was 4.5 % or more off, a few 8-10 %), so the rows measured before
// the pool is formed wait for it: at most kMaxWaiting rows, a layer's end
// or the scan's end, after which they go out with their own shapes.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "libbead/part/hidden_groove.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

class LayerGrooves {
 public:
  using Emit = std::function<void(const PartGeometryRow&)>;
  static constexpr std::size_t kPoolProfiles = 25;
  static constexpr std::size_t kMaxWaiting = 4 * kPoolProfiles;
  static constexpr std::size_t kMinExponents = 5;

  // A measured row, in the scan's order, with its points and the surface
  // below them (nullptr: no groove to estimate: the bead not valid, no
  // surface below); rows go to `emit` in the same order, once corrected.
  void Add(PartGeometryRow row, const StoredProfile* points, const SurfaceGrid* under, const Emit& emit);
  // The rows still waiting, with their own fits (the scan's end).
  void Flush(const Emit& emit);
  // Each layer's pooled shape, in the order they were formed.
  const std::vector<std::pair<int64_t, PooledShape>>& pools() const { return pools_; }

 private:
  struct Waiting {
    PartGeometryRow row;
    std::optional<StoredProfile> points;
    std::optional<SurfaceGrid> under;
  };
  HiddenGroove Estimate(const StoredProfile& points, const SurfaceGrid& under, const PartGeometryRow& row,
                        const HiddenGroove* previous, const PooledShape* shape) const;
  void Pool();

  int64_t layer_ = -1;
  std::vector<double> aspects_;
  // The rows placed at their silhouettes: their exponents, and for the
  // pool's sigma what their ends' cells leave.
  struct Placed {
    double exponent, aspect_end_var, exponent_end_var, left_end_mm, spacing_mm;
  };
  std::vector<Placed> placed_;
  std::vector<std::pair<int64_t, PooledShape>> pools_;
  std::optional<PooledShape> pooled_;
  std::optional<HiddenGroove> last_;  // the layer's last fit: where the next starts
  std::vector<Waiting> waiting_;
};

}  // namespace bead::part
