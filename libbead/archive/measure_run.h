// MeasureRun: a whole run's geometry and occlusion correction, streamed.
//
// The profiles are read window by window (io/profile_stream.h), measured
// on every core (each worker its own ProfileProcessor: the same code as
// the real-time path), and let go; the rows wait in an unnamed scratch
// file (gone with the process, even a killed one) until the run's pooled
// occlusion is known, then go to `sink` in profile order. Memory stays
// that of a window whatever the run's length.
//
// The result equals the whole-archive path's: the same processor per
// profile, and the pool fitted on the same profiles (PoolRanks over the
// valid ones), which are read again from the archive by index.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>

#include "libbead/core/rig.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/profile_stream.h"
#include "libbead/occlusion/occlusion_pool.h"
#include "libbead/profile/geometry_row.h"
#include "libbead/profile/profile_processor.h"

namespace bead {

enum class OcclusionMode { kNone, kPooled, kEach };

// "none", "pooled", "each" (what --occlusion takes); throws on anything else.
OcclusionMode ParseOcclusionMode(const std::string& text);

struct MeasureRunOptions {
  ProfileOptions profile;
  OcclusionMode occlusion = OcclusionMode::kPooled;
  // The occlusion fit, needed unless `occlusion` is kNone:
  // occlusion::EstimateOcclusion (link bead::occlusion), or one loaded on
  // demand. bead::archive itself does not link Ceres.
  occlusion::Estimator estimate = nullptr;
  std::size_t window_rows = 4096;  // about this many profiles per window (whole chunks)
  // Called after each window with (profiles measured, total).
  std::function<void(std::size_t, std::size_t)> progress;
};

struct MeasureRunSummary {
  std::size_t profiles = 0, valid = 0;
  std::array<std::size_t, 8> by_status{};  // count per ProfileStatus
  double seconds = 0;                      // reading and measuring
  OcclusionMode occlusion = OcclusionMode::kNone;
  occlusion::PooledOcclusion pooled;          // kPooled
  int each_fitted = 0, each_constrained = 0;  // kEach
};

MeasureRunSummary MeasureRun(ProfileStream& stream, const Rig& rig, WorkerPool& pool, const MeasureRunOptions& options,
                             const std::function<void(const GeometryRow&)>& sink);

// One line on the occlusion stage's outcome ("" for none).
std::string OcclusionLine(const MeasureRunSummary& summary);

}  // namespace bead
