#include "libbead/part/part_flow.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "libbead/core/error.h"

namespace bead::part {

NozzleClock::NozzleClock(const AcquisitionLog& log, const std::string& file) : log_(log) {
  if (!log.part() || log.layer.size() != log.size() || log.path_mm.size() != log.size())
    throw Error(Located(file, "/log", "holds no /log/layer and /log/path_mm: the flow along the path needs them"));
  // A forward stretch: consecutive samples of one layer whose path grows.
  std::size_t start = 0;
  for (std::size_t i = 1; i <= log.size(); ++i) {
    const bool ends = i == log.size() || log.layer[i] != log.layer[start] || !(log.path_mm[i] > log.path_mm[i - 1]);
    if (!ends) continue;
    if (i - 1 > start) forward_[log.layer[start]].push_back({start, i - 1});
    start = i;
  }
}

double NozzleClock::SpeedAt(std::size_t i, double t) const {
  if (!log_.head_speed_mm_s.empty()) {
    const double w = (t - log_.t_s[i]) / (log_.t_s[i + 1] - log_.t_s[i]);
    return (1 - w) * log_.head_speed_mm_s[i] + w * log_.head_speed_mm_s[i + 1];
  }
  return (log_.path_mm[i + 1] - log_.path_mm[i]) / (log_.t_s[i + 1] - log_.t_s[i]);
}

std::optional<NozzleClock::Passing> NozzleClock::At(int64_t layer, double path) const {
  const auto it = forward_.find(layer);
  if (it == forward_.end()) return std::nullopt;
  for (const auto& [first, last] : it->second) {
    if (path < log_.path_mm[first] || path > log_.path_mm[last]) continue;
    // The path grows strictly within a stretch: a binary search.
    const auto begin = log_.path_mm.begin();
    const auto up = std::upper_bound(begin + first, begin + last + 1, path);
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(up - begin), last) - 1;
    const double w = (path - log_.path_mm[i]) / (log_.path_mm[i + 1] - log_.path_mm[i]);
    Passing p;
    p.t_s = log_.t_s[i] + w * (log_.t_s[i + 1] - log_.t_s[i]);
    p.head_speed_mm_s = SpeedAt(i, p.t_s);
    p.screw_rpm = (1 - w) * log_.screw_rpm[i] + w * log_.screw_rpm[i + 1];
    return p;
  }
  return std::nullopt;
}

PartFlowRow FlowOf(const PartGeometryRow& g, const NozzleClock& clock) {
  PartFlowRow r;
  r.profile = g.profile;
  r.layer = g.layer;
  r.path_mm = g.path_mm;
  const std::optional<NozzleClock::Passing> p = clock.At(g.layer, g.path_mm);
  if (p) {
    r.t_s = p->t_s;
    r.head_speed_mm_s = p->head_speed_mm_s;
    r.screw_rpm = p->screw_rpm;
  }
  if (!p || !g.bead.valid()) return r;
  r.area_mm2 = g.bead.area_mm2;
  r.area_corrected_mm2 = g.area_corrected_mm2;
  r.flow_mm3_s = p->head_speed_mm_s * r.Area();
  r.valid = true;
  return r;
}

void LayerVolumes::Add(const PartFlowRow& r) {
  if (!r.valid) return;
  const double area = r.Area();
  double& v = volume_[r.layer];
  if (const auto it = last_.find(r.layer); it != last_.end() && r.path_mm > it->second.first)
    v += 0.5 * (area + it->second.second) * (r.path_mm - it->second.first);
  last_[r.layer] = {r.path_mm, area};
}

void SpeedAndArea::Add(const PartFlowRow& row) {
  if (!row.valid || !(row.head_speed_mm_s > 0.0)) return;
  speed_.push_back(row.head_speed_mm_s);
  area_.push_back(row.Area());
  flow_.push_back(row.flow_mm3_s);
}

CornerBulge SpeedAndArea::Bulge(double fraction) const {
  CornerBulge b;
  if (speed_.empty()) return b;
  std::vector<double> v = speed_;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  const double limit = fraction * v[v.size() / 2];
  double area[2] = {0, 0}, flow[2] = {0, 0}, speed[2] = {0, 0};
  std::size_t n[2] = {0, 0};
  for (std::size_t i = 0; i < speed_.size(); ++i) {
    const int k = speed_[i] < limit ? 0 : 1;
    ++n[k], area[k] += area_[i], flow[k] += flow_[i], speed[k] += speed_[i];
  }
  b.slow = n[0], b.rest = n[1];
  if (!n[0] || !n[1]) return b;
  b.slow_speed_mm_s = speed[0] / n[0], b.rest_speed_mm_s = speed[1] / n[1];
  b.area_excess = (area[0] / n[0]) / (area[1] / n[1]) - 1.0;
  b.flow_excess = (flow[0] / n[0]) / (flow[1] / n[1]) - 1.0;
  return b;
}

double PartScanFlow::TotalVolume() const {
  double total = 0.0;
  for (const auto& [layer, v] : volumes_mm3) total += v;
  return total;
}

PartScanFlow MeasurePartScanFlow(const std::string& path, const PartPlaces& places, const AcquisitionLog* log,
                                 const Rig& rig, const MeasurePartOptions& options, unsigned threads,
                                 const std::function<void(const PartGeometryRow&)>& on_geometry,
                                 const std::function<void(const PartFlowRow&)>& on_flow,
                                 const std::function<void(std::size_t, std::size_t)>& progress) {
  PartScanFlow out;
  std::optional<NozzleClock> clock;
  if (log) clock.emplace(*log, path);
  out.has_flow = clock.has_value();
  LayerVolumes volumes;
  SpeedAndArea speeds;
  out.layers = MeasurePartFile(
      path, places, rig, options, threads,
      [&](const PartGeometryRow& g) {
        if (on_geometry) on_geometry(g);
        if (!clock) return;
        const PartFlowRow row = FlowOf(g, *clock);
        out.flow_samples += row.valid;
        out.unplaced += std::isnan(row.t_s);
        volumes.Add(row);
        speeds.Add(row);
        if (on_flow) on_flow(row);
      },
      progress);
  out.volumes_mm3 = volumes.volumes_mm3();
  out.bulge = speeds.Bulge();
  return out;
}

}  // namespace bead::part
