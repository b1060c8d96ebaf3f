// Where the points of a prepared set lie in the view, and index searches
// on its x (compiled once: not part of the per-processor kernel).
#include <algorithm>

#include "libbead/profile/point_set.h"

namespace bead {

int32_t ViewIndex(const PointSet& p, const ProfileWorkspace& w, std::size_t k) {
  // The group of eight holding the k-th finite point from heights_begin:
  // at or after group k / 8 (each group holds at most eight), before the
  // first that has more than k finite points before it.
  const std::size_t groups = (w.heights_end - w.heights_begin + 7) / 8;
  std::size_t g = k / 8;
  while (g + 1 < groups && static_cast<std::size_t>(w.kept_before[g + 1]) <= k) ++g;
  std::size_t i = w.heights_begin + 8 * g;
  for (std::size_t before = static_cast<std::size_t>(w.kept_before[g]);; ++i)
    if ((p.z[i] - p.z[i]) == 0.0f && before++ == k) break;
  return w.mapped ? w.map[i] : static_cast<int32_t>(i);
}

std::size_t LowerIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::lower_bound(p.x, p.x + p.n, value, [](float a, double v) { return a < v; }) - p.x);
}

std::size_t UpperIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::upper_bound(p.x, p.x + p.n, value, [](double v, float a) { return v < a; }) - p.x);
}

}  // namespace bead
