#include "libbead/part/part_flow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/core/median.h"
#include "libbead/part/flow_hampel.h"

namespace bead::part {

namespace {

// The log's monotone stretches, each within one layer, the path growing or
// falling from sample to sample.
struct Stretches {
  std::map<int64_t, std::vector<std::pair<std::size_t, std::size_t>>> each_way[2];  // [0] backward, [1] forward
};

Stretches MonotoneStretches(const AcquisitionLog& log) {
  Stretches out;
  const auto& path = log.path_mm;
  for (std::size_t i = 0; i + 1 < log.size();) {
    if (log.layer[i + 1] != log.layer[i] || !std::isfinite(path[i]) || !std::isfinite(path[i + 1]) ||
        path[i + 1] == path[i]) {
      ++i;  // a new layer, a place not known, or the nozzle standing still
      continue;
    }
    const bool forward = path[i + 1] > path[i];
    std::size_t j = i + 1;
    while (j + 1 < log.size() && log.layer[j + 1] == log.layer[i] &&
           (forward ? path[j + 1] > path[j] : path[j + 1] < path[j]))
      ++j;
    out.each_way[forward][log.layer[i]].push_back({i, j});
    i = j;  // a turn's sample ends one stretch and starts the next
  }
  return out;
}

// The screw's revolutions over a stretch (rpm over minutes; none where the
// log holds no screw speed), and its time.
std::pair<double, double> TurnsAndTime(const AcquisitionLog& log, std::size_t first, std::size_t last) {
  const double time = log.t_s[last] - log.t_s[first];
  if (log.screw_rpm.size() != log.size()) return {0.0, time};
  double turns = 0.0;
  for (std::size_t i = first; i < last; ++i)
    turns += 0.5 * (std::max(log.screw_rpm[i], 0.0) + std::max(log.screw_rpm[i + 1], 0.0)) *
             (log.t_s[i + 1] - log.t_s[i]) / 60.0;
  return {turns, time};
}

}  // namespace

NozzleClock::NozzleClock(const AcquisitionLog& log, const std::string& file) : log_(log) {
  if (!log.part() || log.layer.size() != log.size() || log.path_mm.size() != log.size())
    throw Error(Located(file, "/log", "holds no /log/layer and /log/path_mm: the flow along the path needs them"));
  const Stretches all = MonotoneStretches(log);
  std::map<int64_t, double> turns[2], time[2];
  for (int way = 0; way < 2; ++way)
    for (const auto& [layer, stretches] : all.each_way[way])
      for (const auto& [first, last] : stretches) {
        const auto [n, t] = TurnsAndTime(log, first, last);
        turns[way][layer] += n, time[way][layer] += t;
      }
  for (int way = 0; way < 2; ++way)
    for (const auto& [layer, stretches] : all.each_way[way]) {
      const bool turned = turns[0][layer] > 0.0 || turns[1][layer] > 0.0;
      const double mine = turned ? turns[way][layer] : time[way][layer];
      const double other = turned ? turns[1 - way][layer] : time[1 - way][layer];
      if (way == 1 ? !(mine >= other) : !(mine > other)) continue;
      for (const auto& [first, last] : stretches) printing_[layer].push_back({first, last, way == 1});
    }
  CheckLoggedSpeed(file);
}

void NozzleClock::CheckLoggedSpeed(const std::string& file) const {
  if (log_.head_speed_mm_s.size() != log_.size()) return;
  std::vector<double> ratio;
  for (const auto& [layer, stretches] : printing_)
    for (const Stretch& s : stretches)
      for (std::size_t i = s.first; i < s.last; ++i) {
        const double moved = std::abs(log_.path_mm[i + 1] - log_.path_mm[i]) / (log_.t_s[i + 1] - log_.t_s[i]);
        const double logged = 0.5 * (std::abs(log_.head_speed_mm_s[i]) + std::abs(log_.head_speed_mm_s[i + 1]));
        if (moved > 0.0 && std::isfinite(logged / moved)) ratio.push_back(logged / moved);
      }
  if (ratio.empty()) return;
  const double middle = MiddleInPlace(ratio);
  if (middle >= kLoggedSpeedLow && middle <= 1.0 / kLoggedSpeedLow) return;
  char what[400];
  std::snprintf(what, sizeof what,
                "is %.3g times the speed /log/path_mm moves at while printing (the median over %zu log intervals): "
                "a speed in other units (mm/min is 60 times mm/s), of another axis, or a commanded feed rate the "
                "head did not reach; the flow would be off by as much. Convert it to mm/s along the path, or write "
                "the log without it (the speed is then taken from the path)",
                middle, ratio.size());
  throw Error(Located(file, "/log/head_speed_mm_s", what));
}

int NozzleClock::Direction(int64_t layer) const {
  const auto it = printing_.find(layer);
  return it == printing_.end() ? 0 : it->second.front().forward ? 1 : -1;
}

std::pair<double, double> NozzleClock::Within(std::size_t i, double w) const {
  const double dt = log_.t_s[i + 1] - log_.t_s[i];
  const double mean = std::abs(log_.path_mm[i + 1] - log_.path_mm[i]) / dt;
  if (log_.head_speed_mm_s.size() != log_.size()) return {w, mean};
  // v(u) = v0 + (v1 - v0) u + c u (1 - u) over the fraction u of the time,
  // its mean over the interval v0 / 2 + v1 / 2 + c / 6 the path's.
  const double v0 = std::abs(log_.head_speed_mm_s[i]), v1 = std::abs(log_.head_speed_mm_s[i + 1]);
  const double c = 6.0 * (mean - 0.5 * (v0 + v1));
  const auto v = [&](double u) { return v0 + (v1 - v0) * u + c * u * (1.0 - u); };
  const double vertex = c != 0.0 ? 0.5 + 0.5 * (v1 - v0) / c : 0.0;
  const bool moving = v0 > 0.0 && v1 > 0.0 && (c >= 0.0 || vertex <= 0.0 || vertex >= 1.0 || v(vertex) > 0.0);
  if (!moving || !std::isfinite(c)) return {w, (1 - w) * v0 + w * v1};
  // The time u where the path walked, v0 u + (v1 - v0) u^2 / 2 + c (u^2 / 2
  // - u^3 / 3), reaches w of the interval's (mean): Newton's steps from w,
  // kept in [0, 1] (the path increasing in u: a few steps).
  const double goal = w * mean;
  double u = w;
  for (int k = 0; k < 8; ++k) {
    const double walked = v0 * u + 0.5 * (v1 - v0) * u * u + c * (0.5 * u * u - u * u * u / 3.0);
    u = std::clamp(u - (walked - goal) / v(u), 0.0, 1.0);
  }
  return {u, v(u)};
}

std::optional<NozzleClock::Passing> NozzleClock::At(int64_t layer, double path) const {
  const auto it = printing_.find(layer);
  if (it == printing_.end()) return std::nullopt;
  for (const Stretch& s : it->second) {
    const double a = log_.path_mm[s.first], b = log_.path_mm[s.last];
    if (path < std::min(a, b) || path > std::max(a, b)) continue;
    // The path strictly monotone within a stretch: a binary search.
    const auto begin = log_.path_mm.begin() + static_cast<std::ptrdiff_t>(s.first);
    const auto end = log_.path_mm.begin() + static_cast<std::ptrdiff_t>(s.last) + 1;
    const auto up =
        s.forward ? std::upper_bound(begin, end, path) : std::upper_bound(begin, end, path, std::greater<>());
    const std::size_t i = std::min<std::size_t>(s.first + static_cast<std::size_t>(up - begin), s.last) - 1;
    const double w = (path - log_.path_mm[i]) / (log_.path_mm[i + 1] - log_.path_mm[i]);
    const auto [u, speed] = Within(i, w);
    Passing p;
    p.t_s = log_.t_s[i] + u * (log_.t_s[i + 1] - log_.t_s[i]);
    p.head_speed_mm_s = speed;
    p.screw_rpm = log_.screw_rpm.size() == log_.size() ? (1 - u) * log_.screw_rpm[i] + u * log_.screw_rpm[i + 1] : NAN;
    return p;
  }
  return std::nullopt;
}

PartFlowRow FlowOf(const PartGeometryRow& g, const NozzleClock& clock, bool corrected) {
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
  if (corrected && std::isnan(r.area_corrected_mm2)) return r;
  r.flow_mm3_s = p->head_speed_mm_s * r.Area();
  r.flow_sigma_mm3_s = p->head_speed_mm_s * g.area_corrected_sigma_mm2;
  r.valid = true;
  return r;
}

void LayerVolumes::Add(const PartFlowRow& r) {
  if (!r.valid) return;
  const double area = r.Area();
  const auto [it, first] = layers_.try_emplace(r.layer);
  Layer& l = it->second;
  if (!first && r.path_mm != l.path_mm) {
    const int way = r.path_mm > l.path_mm ? 1 : 0;
    const double step = std::abs(r.path_mm - l.path_mm);
    l.way[way] += 0.5 * (area + l.area_mm2) * step, l.covered[way] += step;
  }
  l.path_mm = r.path_mm, l.area_mm2 = area;
}

std::map<int64_t, double> LayerVolumes::volumes_mm3() const {
  std::map<int64_t, double> out;
  for (const auto& [layer, l] : layers_) out[layer] = l.covered[1] >= l.covered[0] ? l.way[1] : l.way[0];
  return out;
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
  const double limit = fraction * MiddleInPlace(v);
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

void PartScanFlow::ScanDelay::Add(double delay_s) {
  ++rows, sum_s += delay_s, early += delay_s < -kEarlyS;
  min_s = std::min(min_s, delay_s), max_s = std::max(max_s, delay_s);
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
  FlowHampel filter;
  const FlowHampel::Emit emit = [&](const PartFlowRow& row) {
    out.flow_samples += row.valid;
    out.unplaced += std::isnan(row.t_s);
    volumes.Add(row);
    speeds.Add(row);
    if (on_flow) on_flow(row);
  };
  out.layers = MeasurePartFile(
      path, places, rig, options, threads,
      [&](const PartGeometryRow& g) {
        if (on_geometry) on_geometry(g);
        if (!clock) return;
        const PartFlowRow row = FlowOf(g, *clock, options.correct_hidden);
        if (std::isfinite(row.t_s)) out.delay.Add(g.t_s - row.t_s);
        filter.Add(row, emit);
      },
      progress);
  filter.Flush(emit);
  out.replaced = filter.replaced();
  out.volumes_mm3 = volumes.volumes_mm3();
  out.bulge = speeds.Bulge();
  return out;
}

}  // namespace bead::part
