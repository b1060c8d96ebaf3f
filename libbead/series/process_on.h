// Where a measured process ran: the stretches of a record to fit, and the
// rest reported with its reason, never fitted as dynamics.
//  - a gap: no sample (or no finite output) for more than `gap_steps`
//    median sample steps: the record is split there;
//  - process off: the output at its zero floor (within `zero_fraction` of
//    its 95th percentile of |y|) for `min_off_samples` or more samples in a
//    row while the input is not at zero: the arc or the extruder off, the
//    start before material arrives. Applies only to an output that has a
//    floor at zero (a width, an area, a flow: nothing below
//    -zero_fraction of that scale); an input also at zero is rest, which a
//    model from rest predicts, so it stays.
// A stretch that follows a process-off one and whose output rises from its
// zero floor (the first sample closer to zero than `start_fraction` of the
// stretch's median output, as a bead's width grows from nothing when the
// arc strikes) is where the process started: Segment::process_starts, its
// state at rest. One whose output jumps straight back to its level was
// running all along (the output read zero, the process did not stop): its
// state is estimated like any stretch's.
#pragma once

#include <string>
#include <vector>

#include "libbead/core/segment.h"

namespace bead {

struct Exclusion {
  double t_begin_s = 0.0, t_end_s = 0.0;
  std::string reason;  // "process off", "no samples"
};

struct ProcessOnOptions {
  double gap_steps = 5.0;
  double zero_fraction = 0.02;
  int min_off_samples = 3;
  int min_segment_samples = 10;  // shorter stretches are left out too ("too short to fit")
  double start_fraction = 0.5;   // "closer to the off level than to the running one"
};

struct ProcessOn {
  std::vector<Segment> segments;
  std::vector<Exclusion> excluded;
  std::size_t fitted_samples = 0;
};

ProcessOn FindProcessOn(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                        const ProcessOnOptions& options = {});

// "process off 52.10-55.90 s; no samples 12.00-13.50 s" (empty when nothing was left out).
std::string DescribeExclusions(const std::vector<Exclusion>& excluded);

}  // namespace bead
