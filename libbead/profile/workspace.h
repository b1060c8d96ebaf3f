// ProfileWorkspace: the buffers one profile's geometry needs. Sized once for
// the longest profile expected, then reused, so the per-profile path does
// not allocate (acquisition software calls it at the sensor's rate). The
// buffers always hold `capacity()` elements; the counts say how many of
// them the current profile uses (resizing would re-initialise them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bead {

struct ProfileWorkspace {
  // Valid points inside the left and right reference areas.
  std::vector<double> left_x, left_z, right_x, right_z;
  std::size_t n_left = 0, n_right = 0;
  // Scratch for medians (small, reserved).
  std::vector<double> scratch;
  // Valid points in x order: original index, x, along-line s, height h.
  std::vector<int32_t> order;
  std::vector<double> x, s, h;
  std::vector<uint8_t> keep;
  std::size_t n_valid = 0;  // entries of order (then of x, s, h once computed)

  explicit ProfileWorkspace(std::size_t points = 0) { Reserve(points); }
  void Reserve(std::size_t points);
  std::size_t capacity() const { return order.size(); }
};

}  // namespace bead
