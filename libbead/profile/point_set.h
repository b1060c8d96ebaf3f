// PointSet: a profile's points with finite x in increasing x, the form
// every later stage works on; a non-finite z marks a dropout, which the
// later stages skip. A sensor that reports x in order (the usual case, NaN
// z where it saw nothing) is used as it is, without a copy; reversed or
// unsorted x, or a non-finite x, gets a sorted copy of the points with a
// finite x (dropouts kept in place).
// The workspace remembers how to map a point back to its index in the view.
#pragma once

#include <cstddef>
#include <cstdint>

#include "libbead/core/profile_view.h"
#include "libbead/profile/workspace.h"

namespace bead {

struct PointSet {
  const float* x = nullptr;  // finite, increasing (ties allowed)
  const float* z = nullptr;  // non-finite: a dropout
  std::size_t n = 0;
};

// Grows the workspace only if the view is longer than its capacity.
PointSet PreparePoints(const ProfileView& view, ProfileWorkspace& workspace);

// How many of the points [begin, end) have a finite z.
std::size_t CountFiniteZ(const PointSet& points, std::size_t begin, std::size_t end);

// Index of the first point with x >= value (n if none), and of the first with x > value.
std::size_t LowerIndex(const PointSet& points, double value);
std::size_t UpperIndex(const PointSet& points, double value);
// The same, trying `hint` first (an index found for an earlier profile)
// and updating it: O(1) when the x grid has not changed (inline: the
// kernel checks six hints per profile).
inline std::size_t LowerIndex(const PointSet& p, double value, std::size_t& hint) {
  const std::size_t h = hint;
  if (h <= p.n && (h == 0 || p.x[h - 1] < value) && (h == p.n || !(p.x[h] < value))) return h;
  return hint = LowerIndex(p, value);
}
inline std::size_t UpperIndex(const PointSet& p, double value, std::size_t& hint) {
  const std::size_t h = hint;
  if (h <= p.n && (h == 0 || !(value < p.x[h - 1])) && (h == p.n || value < p.x[h])) return h;
  return hint = UpperIndex(p, value);
}

}  // namespace bead
