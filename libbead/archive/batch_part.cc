#include "libbead/archive/batch_part.h"

#include <cmath>
#include <filesystem>
#include <optional>

#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_csv.h"
#include "libbead/part/part_flow.h"

namespace bead {

void ProcessPartScan(const BatchRun& job, const std::string& dir, const BatchOptions& options, RunResult& r) {
  const RigFile rig = ReadPartRigFile(job.rig);
  r.warnings.insert(r.warnings.end(), rig.warnings.begin(), rig.warnings.end());
  const RunArchive scan = ReadPartScan(job.run, /*with_profiles=*/false, /*with_log=*/true);
  const part::MeasurePartOptions measure = part::PartOptionsFor(options.profile);
  part::PartGeometryCsvWriter geometry(dir + "/geometry.csv");
  std::optional<part::PartFlowCsvWriter> flow;
  if (scan.log) flow.emplace(dir + "/flow.csv");
  double seen = 0.0, corrected = 0.0;
  const part::PartScanFlow measured = part::MeasurePartScanFlow(
      job.run, *scan.part, scan.log ? &*scan.log : nullptr, rig.rig, measure, 1,
      [&](const part::PartGeometryRow& g) {
        geometry.Append(g);
        if (g.bead.valid() && std::isfinite(g.area_corrected_mm2))
          seen += g.bead.area_mm2, corrected += g.area_corrected_mm2;
      },
      [&](const part::PartFlowRow& row) { flow->Append(row); });
  geometry.Commit();
  for (const part::LayerSummary& l : measured.layers) {
    r.profiles += l.profiles, r.valid += l.valid;
    if (l.layer > 0 && l.no_surface_below == l.profiles)
      r.warnings.push_back("layer " + std::to_string(l.layer) + ": layer " + std::to_string(l.layer - 1) +
                           " is not in the scan: nothing to measure it against");
    if (!l.bed_off_mm.empty())
      r.warnings.push_back("layer " + std::to_string(l.layer) + ": " + std::to_string(l.bed_off_mm.size()) +
                           " profiles' bare bed lies off the layer below's (bed_moved): frame_z_mm or z is not "
                           "the bed frame's height");
    if (!l.under_mm.empty())
      r.warnings.push_back("layer " + std::to_string(l.layer) + ": " + std::to_string(l.under_mm.size()) +
                           " profiles lie under the surface before them (under_surface_below): " +
                           (l.layer > 0 ? "frame_z_mm is not the head's height"
                                        : "z is a distance, not a height, or the reference areas are not on the bed"));
  }
  if (seen > 0.0) r.occlusion_fraction = 1.0 - corrected / seen;
  if (!flow) {
    r.warnings.push_back("no flow: /log missing (the flow along the path needs the nozzle's log)");
    return;
  }
  flow->Commit();
  r.flow_samples = measured.flow_samples;
  r.total_volume_mm3 = measured.TotalVolume();
}

}  // namespace bead
