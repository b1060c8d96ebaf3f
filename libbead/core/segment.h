// A stretch of samples [begin, end) of a measured series through which the
// process ran: identification simulates each as one, with an initial state
// of its own; between stretches the process was off or not measured.
#pragma once

#include <cstddef>
#include <vector>

namespace bead {

struct Segment {
  std::size_t begin = 0, end = 0;
};

// One segment covering every sample.
inline std::vector<Segment> WholeRecord(std::size_t n) { return {Segment{0, n}}; }

}  // namespace bead
