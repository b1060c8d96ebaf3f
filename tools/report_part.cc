#include "tools/report_part.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/part_csv.h"
#include "libbead/part/part_flow.h"
#include "tools/rig_input.h"
#include "tools/tty_progress.h"

namespace bead::tools {
namespace {

namespace fs = std::filesystem;

// A profile of each layer is drawn where it stands within this of a place.
constexpr double kNearMm = 5.0;

// Three places along the path that every layer passes (else layer 0's
// stretch): a sixth in from each end, and the middle.
std::vector<double> SectionPlaces(const std::vector<part::LayerSummary>& layers) {
  if (layers.empty()) return {};
  double lo = layers.front().first_path_mm, hi = layers.front().last_path_mm;
  for (const auto& l : layers) lo = std::max(lo, l.first_path_mm), hi = std::min(hi, l.last_path_mm);
  if (!(hi > lo)) lo = layers.front().first_path_mm, hi = layers.front().last_path_mm;
  return {lo + (hi - lo) / 6.0, 0.5 * (lo + hi), hi - (hi - lo) / 6.0};
}

// Each place's nearest profile of each layer (within kNearMm): place, layer -> profile.
std::map<std::pair<std::size_t, int64_t>, std::size_t> SectionProfiles(const PartPlaces& p,
                                                                       const std::vector<double>& places) {
  std::map<std::pair<std::size_t, int64_t>, std::size_t> best;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t k = 0; k < places.size(); ++k) {
      const double d = std::abs(p.path_mm[i] - places[k]);
      if (!(d <= kNearMm)) continue;
      const auto key = std::make_pair(k, p.layer[i]);
      const auto it = best.find(key);
      if (it == best.end() || d < std::abs(p.path_mm[it->second] - places[k])) best[key] = i;
    }
  return best;
}

void WriteSections(const std::string& run, const PartPlaces& p, const std::vector<double>& places,
                   const fs::path& file) {
  WorkerPool pool(1);
  const std::unique_ptr<ProfileStream> stream = OpenPartProfiles(run, pool);
  ProfileBlock block;
  std::ofstream out(file);
  out << "section,place_mm,layer,profile,path_mm,x_mm,z_mm\n";
  for (const auto& [key, i] : SectionProfiles(p, places)) {
    stream->Read(i, 1, block);
    const ProfileView v = block.view(0);
    for (std::size_t k = 0; k < v.x_mm.size(); ++k)
      if (std::isfinite(v.x_mm[k]) && std::isfinite(v.z_mm[k]))
        out << key.first << ',' << places[key.first] << ',' << key.second << ',' << i << ',' << p.path_mm[i] << ','
            << v.x_mm[k] + p.frame_x_mm[i] << ',' << v.z_mm[k] + p.frame_z_mm[i] << '\n';
  }
}

void WriteLayers(const part::PartScanFlow& f, const fs::path& file) {
  std::ofstream out(file);
  out << "layer,profiles,valid,no_surface_below,mean_area_mm2,mean_area_corrected_mm2,shift_mm,volume_mm3\n";
  for (const part::LayerSummary& l : f.layers) {
    const auto v = f.volumes_mm3.find(l.layer);
    out << l.layer << ',' << l.profiles << ',' << l.valid << ',' << l.no_surface_below << ',' << l.MeanArea() << ','
        << l.MeanCorrected() << ',' << (l.shift_found ? l.MedianShift() : NAN) << ','
        << (v == f.volumes_mm3.end() ? NAN : v->second) << '\n';
  }
}

}  // namespace

void WritePartReportData(const std::string& rig_path, const std::string& run, const ProfileOptions& bed,
                         const fs::path& dir) {
  const RunArchive scan = ReadPartScan(run, /*with_profiles=*/false, /*with_log=*/true);
  const RigFile rig = ReadPartRigFile(rig_path);
  SayRigWarnings(rig);
  const part::MeasurePartOptions options = part::PartOptionsFor(bed);
  part::PartGeometryCsvWriter geometry((dir / "part_geometry.csv").string());
  std::optional<part::PartFlowCsvWriter> flow;
  if (scan.log) flow.emplace((dir / "part_flow.csv").string());
  const part::PartScanFlow f = part::MeasurePartScanFlow(
      run, *scan.part, scan.log ? &*scan.log : nullptr, rig.rig, options, 0,
      [&](const part::PartGeometryRow& g) { geometry.Append(g); },
      [&](const part::PartFlowRow& row) { flow->Append(row); }, TtyProgress("measured"));
  geometry.Commit();
  if (flow) flow->Commit();
  WriteLayers(f, dir / "layers.csv");
  WriteSections(run, *scan.part, SectionPlaces(f.layers), dir / "sections.csv");
  const part::CornerBulge& b = f.bulge;
  std::ofstream about(dir / "about.csv");
  about << "kind,run,rig,profiles,flow,unplaced,total_volume_mm3,slow_profiles,slow_speed_mm_s,rest_speed_mm_s,"
           "slow_area_excess,slow_flow_excess\npart,\""
        << run << "\",\"" << rig_path << "\"," << scan.part->size() << ',' << f.has_flow << ',' << f.unplaced << ','
        << (f.has_flow ? f.TotalVolume() : NAN) << ',' << b.slow << ',' << b.slow_speed_mm_s << ',' << b.rest_speed_mm_s
        << ',' << b.area_excess << ',' << b.flow_excess << '\n';
}

}  // namespace bead::tools
