// A stretch of samples [begin, end) of a measured series through which the
// process ran: identification simulates each as one, with an initial state
// of its own; between stretches the process was off or not measured.
#pragma once

#include <cstddef>
#include <vector>

namespace bead {

struct Segment {
  std::size_t begin = 0, end = 0;
  // The process started at the first sample (the stretch follows one where
  // it was off: the arc or the extruder off, no material yet). Its state
  // was at rest there and the input acted only from then on, so nothing
  // about the stretch's start is unknown: no initial state is estimated
  // and no sample is left out. Otherwise (the record's first sample, or
  // after a gap in the record) the state is the process's own, unknown.
  bool process_starts = false;
};

// One segment covering every sample.
inline std::vector<Segment> WholeRecord(std::size_t n) { return {Segment{0, n}}; }

}  // namespace bead
