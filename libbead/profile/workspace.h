// ProfileWorkspace: the buffers one profile's geometry needs. Sized once for
// the longest profile expected, then reused, so the per-profile path does
// not allocate (acquisition software calls it at the sensor's rate).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bead {

struct ProfileWorkspace {
  // Valid points inside the left and right reference areas.
  std::vector<double> left_x, left_z, right_x, right_z;
  // Scratch for medians.
  std::vector<double> scratch;
  // Valid points in x order: original index, x, along-line s, height h.
  std::vector<int32_t> order;
  std::vector<double> x, s, h;
  std::vector<uint8_t> keep;

  explicit ProfileWorkspace(std::size_t points = 0) { Reserve(points); }
  void Reserve(std::size_t points);
  std::size_t capacity() const { return order.capacity(); }
};

}  // namespace bead
