// MeasureWholeRun: a run streamed through MeasureRun, its per-profile
// results kept for the stages that need the whole series (the flow's
// filters, explain): the profiles' points are let go window by window, so
// what stays is about 150 bytes per profile (a profile of 640 points is
// 5 kB), 100 MB for an hour at 200 profiles/s.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "libbead/archive/measure_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/io/run_archive.h"

namespace bead {

struct MeasuredRun {
  // The log and root attributes; run.profiles holds t_s and encoder only.
  RunArchive run;
  std::vector<BeadGeometry> geometry;
  std::vector<double> corrected, bias, sigma;  // the occlusion stage's (NaN: none)
  MeasureRunSummary summary;
};

// `opened`: from OpenRun (check its log first). `row`, when given, also sees every row in order (a geometry CSV written
// on the way).
MeasuredRun MeasureWholeRun(OpenedRun opened, const Rig& rig, WorkerPool& pool, const MeasureRunOptions& options,
                            const std::function<void(const GeometryRow&)>& row = {});

}  // namespace bead
