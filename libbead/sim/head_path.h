// The twin's print head along a layer's toolpath: a straight wall at one
// speed, or a closed contour with rounded corners (a rounded rectangle)
// that the head takes slower, its speed limited by the lateral
// acceleration through a corner (v^2 / R) and by the tangential one on the
// way in and out (the thesis, 1.3.2: the gantry slows entering a corner and
// speeds up leaving it, with the extruder's command unchanged).
#pragma once

#include <vector>

#include "libbead/sim/part_twin.h"

namespace bead::sim {

class HeadPath {
 public:
  explicit HeadPath(const PartTwinConfig& c);
  // The toolpath printed in a layer: the wall's length, the contour's
  // perimeter, mm.
  double length_mm() const { return length_; }
  // The head's speed at p mm along the path (beyond its end, where the
  // profiler still trails it, the head goes on at the nominal speed).
  double SpeedAt(double p) const;
  // When the head passes p, s from the pass's start; and its inverse.
  double TimeAt(double p) const;
  double PathAt(double t) const;
  // The pass: from the start until the profiler has seen the path's end.
  double pass_s() const { return TimeAt(length_ + trail_); }

 private:
  double Sample(const std::vector<double>& v, double p) const;
  double length_ = 0.0, trail_ = 0.0, nominal_ = 1.0;
  double step_ = 0.05;                // mm between samples of the speed
  std::vector<double> speed_, time_;  // at p = k step, k = 0 .. over the path and the trail
};

}  // namespace bead::sim
