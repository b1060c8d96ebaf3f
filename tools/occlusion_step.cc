#include "tools/occlusion_step.h"

#include <cmath>
#include <cstdio>

#include "libbead/occlusion/occlusion_pool.h"

namespace bead::tools {

void AddOcclusionOption(CLI::App* cmd, std::string& mode) {
  cmd->add_option("--occlusion", mode,
                  "Hidden-area correction: pooled (one shape per run), each (a fit per profile), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"pooled", "each", "none"}));
}

OcclusionColumns RunOcclusion(const std::string& mode, const Rig& rig, const ProfileBlock& block,
                              const std::vector<BeadGeometry>& geometry) {
  const std::size_t n = geometry.size();
  OcclusionColumns out{std::vector<double>(n, NAN), std::vector<double>(n, NAN), std::vector<double>(n, NAN)};
  if (mode == "none") return out;
  occlusion::OcclusionOptions options;
  options.laser_origin = rig.laser_origin;
  auto view = [&](std::size_t i) { return block.view(i); };
  if (mode == "pooled") {
    const occlusion::PooledOcclusion pool = occlusion::PoolOcclusion(n, view, geometry, options);
    if (!pool.ok) {
      std::printf("occlusion: %s; no correction\n", pool.note.c_str());
      return out;
    }
    std::printf("occlusion (pooled over %d profiles, mostly %s): hidden area %.2f %% +- %.2f %% of the measured area%s\n",
                pool.fitted, pool.family.c_str(), 100 * pool.bias_fraction, 100 * pool.fraction_sigma,
                pool.constrained ? "" : " -- NOT constrained by the data: read it as a range, not a value");
    for (std::size_t i = 0; i < n; ++i) {
      const occlusion::CorrectedArea c = occlusion::ApplyPooled(pool, geometry[i]);
      out.corrected[i] = c.area_mm2;
      out.bias[i] = c.bias_mm2;
      out.sigma[i] = c.sigma_mm2;
    }
    return out;
  }
  int fitted = 0, constrained = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!geometry[i].valid()) continue;
    const occlusion::OcclusionEstimate e = occlusion::EstimateOcclusion(block.view(i), geometry[i], options);
    if (!e.ok) continue;
    out.corrected[i] = e.corrected_area_mm2;
    out.bias[i] = e.bias_mm2;
    out.sigma[i] = e.sigma_mm2;
    ++fitted;
    constrained += e.constrained;
  }
  std::printf("occlusion (a fit per profile): %d profiles corrected, %d with a hidden part the data constrains\n",
              fitted, constrained);
  return out;
}

}  // namespace bead::tools
