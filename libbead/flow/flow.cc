#include "libbead/flow/flow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "libbead/core/error.h"
#include "libbead/flow/extrusion_time.h"
#include "libbead/core/median.h"
#include "libbead/series/encoder.h"
#include "libbead/series/hampel.h"
#include "libbead/series/interpolate.h"
#include "libbead/series/savgol.h"

namespace bead {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

int SpeedWindowSamples(const FlowOptions& o, double dt) {
  int w = std::max(o.speed_order + 2, static_cast<int>(std::lround(o.speed_window_s / dt)));
  return w % 2 ? w : w + 1;
}

std::vector<double> SurfaceSpeed(const Rig& rig, const std::vector<double>& t, const std::vector<double>& counts,
                                 const FlowOptions& o, int* outliers) {
  if (t.size() < 3) throw Error("surface speed: the log needs at least 3 samples");
  const double dt = MedianStep(t);
  SavgolOptions sg;
  sg.window = std::min(SpeedWindowSamples(o, dt),
                       static_cast<int>(t.size()) % 2 ? static_cast<int>(t.size()) : static_cast<int>(t.size()) - 1);
  sg.order = std::min(o.speed_order, sg.window - 1);
  sg.deriv = 1;
  sg.delta = dt;
  std::vector<double> v = SavgolFilter(counts, sg);
  const HampelResult h = Hampel(v, std::max(1, static_cast<int>(std::lround(o.speed_hampel_s / dt))), o.hampel_nsigma);
  if (outliers) *outliers = h.outliers;
  const double mm_per_count = rig.MmPerCount();
  std::vector<double> out(h.y.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = h.y[i] * mm_per_count;
  return out;
}

double AreaSigmaFloor(const std::vector<BeadGeometry>& geometry) {
  std::vector<double> sigmas;
  for (const BeadGeometry& g : geometry)
    if (g.valid() && std::isfinite(g.area_sigma_mm2)) sigmas.push_back(g.area_sigma_mm2);
  return sigmas.empty() ? 0.0 : MedianInPlace(sigmas.data(), sigmas.size());
}

std::vector<std::string> FlowWarnings(const FlowRunFacts& f) {
  std::vector<std::string> out;
  char buf[320];
  if (f.outside > 0 && f.profiles > 0) {
    std::snprintf(buf, sizeof buf,
                  "%zu of %zu profiles lie outside the acquisition log's time span (log %.3f to %.3f s, profiles "
                  "%.3f to %.3f s): they have no flow; are the two on one clock?",
                  f.outside, f.profiles, f.log_first_s, f.log_last_s, f.profile_first_s, f.profile_last_s);
    out.emplace_back(buf);
  }
  if (f.counts_max - f.counts_min < 1.0) {
    std::snprintf(buf, sizeof buf,
                  "the wheel never moved (the encoder reads %.0f counts throughout the log): no material was carried "
                  "to the laser, so the flow is not measured",
                  f.counts_min);
    out.emplace_back(buf);
  }
  if (f.profiles > 0 && f.beads == 0)
    out.emplace_back("no profile holds a measurable bead: every area is missing or zero");
  if (f.profiles > 0 && f.valid == 0) out.emplace_back("no sample has a flow: the total volume is not a measurement");
  return out;
}

namespace {

void Warn(const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry, const AcquisitionLog& log,
          const std::vector<double>& counts, FlowResult& r) {
  FlowRunFacts f;
  f.profiles = profiles.size();
  for (std::size_t k = 0; k < f.profiles; ++k) {
    f.outside += !(profiles.t_s[k] >= log.t_s.front() && profiles.t_s[k] <= log.t_s.back());
    f.beads += geometry[k].valid();
    f.valid += r.samples[k].valid;
  }
  f.log_first_s = log.t_s.front(), f.log_last_s = log.t_s.back();
  if (f.profiles > 0) f.profile_first_s = profiles.t_s.front(), f.profile_last_s = profiles.t_s.back();
  f.counts_min = f.counts_max = counts.front();
  for (double c : counts) f.counts_min = std::min(f.counts_min, c), f.counts_max = std::max(f.counts_max, c);
  r.warnings = FlowWarnings(f);
}

}  // namespace

FlowResult ComputeFlow(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                       const AcquisitionLog& log, const FlowOptions& o, const std::vector<double>& corrected,
                       const std::vector<double>& corrected_sigma) {
  if (geometry.size() != profiles.size()) throw Error("flow: one geometry per profile is needed");
  if (log.size() < 3)
    throw Error("flow: the acquisition log holds " + std::to_string(log.size()) +
                " sample(s); the wheel's speed needs at least 3");
  FlowResult r;
  const EncoderTrack track = UnwrapEncoder(log.encoder, rig.encoder, log.t_s);
  r.encoder_repairs = track.missed_reads + track.glitches;
  const std::vector<double> speed = SurfaceSpeed(rig, log.t_s, track.counts, o, &r.speed_outliers);
  ExtrusionTimeFinder finder(log.t_s, track.counts);
  finder.BuildIndex();  // one search per profile over the whole log

  const std::size_t n = profiles.size();
  std::vector<double> area(n), area_c(n);
  for (std::size_t k = 0; k < n; ++k) {
    const BeadGeometry& g = geometry[k];
    // No bead on a good reference is a measurement: zero area.
    const double a = g.valid() ? g.area_mm2 : (g.status == ProfileStatus::kNoBead ? 0.0 : kNaN);
    area[k] = a;
    // A profile the occlusion stage gave no value (NaN) keeps its measured area.
    area_c[k] = corrected.size() == n && g.valid() && std::isfinite(corrected[k]) ? corrected[k] : a;
  }
  const double floor = o.area_sigma_floor_mm2 >= 0 ? o.area_sigma_floor_mm2 : AreaSigmaFloor(geometry);
  const HampelResult ha = Hampel(area, o.area_hampel_half, o.hampel_nsigma, floor);
  const HampelResult hc = Hampel(area_c, o.area_hampel_half, o.hampel_nsigma, floor);
  r.area_outliers = ha.outliers;
  std::vector<double> a_f = ha.y, c_f = hc.y;
  if (o.area_smooth_window > 1) {
    SavgolOptions sg;
    sg.window = o.area_smooth_window;
    sg.order = o.area_smooth_order;
    a_f = SavgolFilterGaps(a_f, sg, o.max_fill);
    c_f = SavgolFilterGaps(c_f, sg, o.max_fill);
  }

  r.samples.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    FlowSample& s = r.samples[k];
    s.profile = static_cast<int64_t>(k);
    const double t_k = profiles.t_s[k];
    const double p_k = UnwrapNear(profiles.encoder[k], rig.encoder, finder.PositionAt(t_k));
    const double target = p_k - rig.offset_counts;
    s.t_s = finder.Find(t_k, target);
    s.encoder = RawFromCounts(target, rig.encoder);
    // An eccentric wheel carried this material at its own radius.
    s.surface_speed_mm_s =
        InterpolateLinear(log.t_s.data(), speed.data(), speed.size(), s.t_s) * rig.SurfaceSpeedFactor(p_k);
    s.area_mm2 = a_f[k];
    s.area_corrected_mm2 = c_f[k];
    s.flow_mm3_s = s.surface_speed_mm_s * s.area_corrected_mm2;
    s.occlusion_bias_mm2 = s.area_mm2 - s.area_corrected_mm2;
    s.area_corrected_sigma_mm2 = corrected_sigma.size() == n ? corrected_sigma[k] : kNaN;
    s.flow_sigma_mm3_s = s.surface_speed_mm_s * s.area_corrected_sigma_mm2;
    s.screw_rpm = InterpolateLinear(log.t_s.data(), log.screw_rpm.data(), log.size(), s.t_s);
    s.valid = std::isfinite(s.t_s) && std::isfinite(s.flow_mm3_s);
  }
  Warn(profiles, geometry, log, track.counts, r);
  // Volume: trapezoids over extrusion time between valid samples, gaps bridged.
  const FlowSample* last = nullptr;
  for (const FlowSample& s : r.samples) {
    if (!s.valid) continue;
    if (last && s.t_s > last->t_s) r.total_volume_mm3 += 0.5 * (s.flow_mm3_s + last->flow_mm3_s) * (s.t_s - last->t_s);
    last = &s;
  }
  return r;
}

}  // namespace bead
