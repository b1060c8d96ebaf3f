// The flow along each layer's path filtered as the wheel's area is
// (flow/flow.h: a Hampel filter, +-5 profiles, 3 sigmas; series/hampel.h),
// streamed: a row whose flow leaves the median of its window (the rows of
// its layer either side, in the scan's order) by over 3 sigmas (1.4826
// times their median absolute deviation, at least the median of the
// window's own flow sigmas, v_head times the corrected area's) takes that
// median. On a part the head's speed changes at every corner, and the area
// with it (the corner's bulge): v_head A, the extruder's flow, is what
// stays smooth, so the filter is put to the flow, not the area. A row
// where the layer below steps between its profiles, or the bead changes
// within one, is corrected with a wide sigma (part/surface_below.h
// BelowChange) and can stand apart from its neighbours by several times
// their noise: on a generator's contour with 3 mm corners, 44 of 2277
// rows' flows were 8-40 mm^3/s off a flow whose own noise was 1, and the
// flow along the path fit the melt's 81.9 %.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "libbead/part/part_flow.h"

namespace bead::part {

class FlowHampel {
 public:
  using Emit = std::function<void(const PartFlowRow&)>;
  static constexpr int kHalfWindow = 5;
  static constexpr double kSigmas = 3.0;

  // Takes the next row in the scan's order; rows go to `emit` in the same
  // order, kHalfWindow rows behind (at once at a layer's end).
  void Add(const PartFlowRow& row, const Emit& emit);
  // The rows still held (the scan's end).
  void Flush(const Emit& emit);
  // How many rows' flows were replaced.
  std::size_t replaced() const { return replaced_; }

 private:
  void EmitNext(const Emit& emit);
  std::vector<PartFlowRow> rows_;  // the layer's rows from kHalfWindow before the next one to emit
  std::size_t next_ = 0;           // in rows_
  std::vector<double> flows_, sigmas_, scratch_;
  std::size_t replaced_ = 0;
};

}  // namespace bead::part
