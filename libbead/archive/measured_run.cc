#include "libbead/archive/measured_run.h"

namespace bead {

MeasuredRun MeasureWholeRun(OpenedRun opened, const Rig& rig, WorkerPool& pool, const MeasureRunOptions& options,
                            const std::function<void(const GeometryRow&)>& row) {
  MeasuredRun m;
  m.run = std::move(opened.run);
  const std::size_t n = opened.profiles->size();
  ProfileBlock& clock = m.run.profiles;
  clock.t_s.reserve(n);
  clock.encoder.reserve(n);
  m.geometry.reserve(n);
  m.corrected.reserve(n);
  m.bias.reserve(n);
  m.sigma.reserve(n);
  m.summary = MeasureRun(*opened.profiles, rig, pool, options, [&](const GeometryRow& r) {
    clock.t_s.push_back(r.t_s);
    clock.encoder.push_back(r.encoder);
    m.geometry.push_back(r.geometry);
    m.corrected.push_back(r.area_corrected_mm2);
    m.bias.push_back(r.occlusion_bias_mm2);
    m.sigma.push_back(r.area_corrected_sigma_mm2);
    if (row) row(r);
  });
  return m;
}

}  // namespace bead
