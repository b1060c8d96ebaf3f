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
  // The valid points in increasing x when the view's own arrays cannot be
  // used as they are (point_set.h).
  std::vector<float> x, z;
  // How a point of the point set maps back to the view: when `mapped`, the
  // view index of every point; and, for each group of eight points, how
  // many points with finite z came before it (the heights stage, from
  // heights_begin).
  std::vector<int32_t> map, kept_before;
  bool mapped = false;
  // The points [heights_begin, heights_end) of the set the heights stage
  // took (the bead's search range; heights_begin a multiple of eight).
  std::size_t heights_begin = 0, heights_end = 0;
  // Per point of the point set: along-line position s and height h;
  // spikes (indices into them) are bridged in place.
  std::vector<float> s, h;
  std::vector<int32_t> spikes;
  std::size_t n_spikes = 0;
  // Scratch for the reference line: its samples and residuals; and where
  // the reference areas began and ended on the last profile (a sensor's x
  // rarely changes, so the searches start by checking these).
  std::vector<float> scratch;
  std::size_t area_hints[4] = {};

  explicit ProfileWorkspace(std::size_t points = 0) { Reserve(points); }
  void Reserve(std::size_t points);
  std::size_t capacity() const { return x.size(); }
};

}  // namespace bead
