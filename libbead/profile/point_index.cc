// Where the points of a prepared set lie in the view, and index searches
// on its x (compiled once: not part of the per-processor kernel).
#include <algorithm>

#include "libbead/profile/point_set.h"

namespace bead {

std::size_t KeptToOriginal(const int32_t* removed, std::size_t n_removed, std::size_t k) {
  // The indices are increasing: once one lies beyond k, so do the rest,
  // and k stops growing; so every one can be tested, without a branch.
  for (std::size_t r = 0; r < n_removed; ++r) k += static_cast<std::size_t>(removed[r]) <= k;
  return k;
}

int32_t ViewIndex(const ProfileWorkspace& w, std::size_t k) {
  const std::size_t i = KeptToOriginal(w.removed.data(), w.n_removed, k);
  return w.mapped ? w.map[i] : static_cast<int32_t>(i);
}

std::size_t LowerIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::lower_bound(p.x, p.x + p.n, value, [](float a, double v) { return a < v; }) - p.x);
}

std::size_t UpperIndex(const PointSet& p, double value) {
  return static_cast<std::size_t>(std::upper_bound(p.x, p.x + p.n, value, [](double v, float a) { return v < a; }) - p.x);
}

std::size_t LowerIndex(const PointSet& p, double value, std::size_t& hint) {
  const std::size_t h = hint;
  if (h <= p.n && (h == 0 || p.x[h - 1] < value) && (h == p.n || !(p.x[h] < value))) return h;
  return hint = LowerIndex(p, value);
}

std::size_t UpperIndex(const PointSet& p, double value, std::size_t& hint) {
  const std::size_t h = hint;
  if (h <= p.n && (h == 0 || !(value < p.x[h - 1])) && (h == p.n || value < p.x[h])) return h;
  return hint = UpperIndex(p, value);
}

}  // namespace bead
