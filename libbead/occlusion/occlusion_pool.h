// Per-run pooled occlusion: a bead's shape changes slowly, so the shape
// fits of a few dozen profiles spread over the run give the hidden
// fraction of the area (bias / measured area) for all of them. Per profile
// the correction is then one multiplication. The pooled fraction is the
// median over the fitted profiles; its uncertainty adds the fits' median
// relative uncertainty and their spread (1.4826 MAD); each profile adds its
// own area_sigma_mm2.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libbead/occlusion/occlusion_fit.h"

namespace bead::occlusion {

struct PooledOcclusion {
  bool ok = false;
  bool constrained = false;
  double bias_fraction = 0;   // bias / measured area
  double fraction_sigma = 0;  // its standard uncertainty
  std::string family;         // most often the heaviest
  int fitted = 0;
  std::string note;
};

struct CorrectedArea {
  double area_mm2, bias_mm2, sigma_mm2;
};

// The pool of a run held whole: PoolRanks, EstimateOcclusion on each,
// PoolFromFits. Defined with the fit in bead::occlusion (Ceres).
PooledOcclusion PoolOcclusion(std::size_t count, const std::function<ProfileView(std::size_t)>& view,
                              const std::vector<BeadGeometry>& geometry, const OcclusionOptions& options,
                              int max_fits = 60);

// The same in two steps, for a run streamed window by window: which of the
// V valid profiles to fit (ranks 0..V-1 among them, in order), then the
// pool from their fits, made elsewhere (in parallel): fits[j] of geometry[j].
std::vector<std::size_t> PoolRanks(std::size_t valid_count, int max_fits = 60);
PooledOcclusion PoolFromFits(const std::vector<OcclusionEstimate>& fits, const std::vector<BeadGeometry>& geometry);

CorrectedArea ApplyPooled(const PooledOcclusion& pooled, const BeadGeometry& geometry);

}  // namespace bead::occlusion
