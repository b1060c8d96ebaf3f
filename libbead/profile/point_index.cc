// Index searches on a prepared set's x (compiled once: not part of the
// per-processor kernel).
#include <algorithm>

#include "libbead/profile/point_set.h"

namespace bead {

std::size_t LowerIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::lower_bound(p.x, p.x + p.n, value, [](float a, double v) { return a < v; }) -
                                  p.x);
}

std::size_t UpperIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::upper_bound(p.x, p.x + p.n, value, [](double v, float a) { return v < a; }) -
                                  p.x);
}

}  // namespace bead
