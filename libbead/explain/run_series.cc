#include "libbead/explain/run_series.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "libbead/flow/extrusion_time.h"
#include "libbead/model/identify.h"
#include "libbead/model/lti_response.h"
#include "libbead/core/median.h"
#include "libbead/series/encoder.h"
#include "libbead/series/interpolate.h"

namespace bead::explain {
namespace {

// What the shift hook needs, kept alive by the hook.
struct RunState {
  std::vector<double> log_t, log_counts, speed, model_flow;
  std::unique_ptr<ExtrusionTimeFinder> finder;
  std::vector<double> counts_measured, area;
  std::vector<ExtrusionTimeFinder::Start> start;  // each profile's search start, the same at every shift
  double offset = 0.0;
};

}  // namespace

RunSeries MakeRunSeries(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                        const AcquisitionLog& log, const FlowResult& flow, const model::TransferFunction& tf,
                        double model_offset, const FlowOptions& flow_options) {
  auto st = std::make_shared<RunState>();
  st->log_t = log.t_s;
  st->log_counts = UnwrapEncoder(log.encoder, rig.encoder, log.t_s).counts;
  st->speed = SurfaceSpeed(rig, st->log_t, st->log_counts, flow_options);
  st->model_flow = model::Predict(tf, model_offset, log.t_s, log.screw_rpm, {});
  std::vector<double> den = tf.den;
  for (double& c : den) c /= tf.den[0];
  const auto basis = model::FilterBasis(den, tf.delay_s, log.t_s, log.screw_rpm, WholeRecord(log.size()));
  const model::StateResponses free =
      model::ComputeStateResponses(den, tf.delay_s, log.t_s, log.screw_rpm, WholeRecord(log.size()));
  st->finder = std::make_unique<ExtrusionTimeFinder>(st->log_t, st->log_counts);
  st->finder->BuildIndex();  // a search per sample for every shift tried
  st->offset = rig.offset_counts;
  // The screw's angle: the integral of its speed.
  std::vector<double> screw(log.size(), 0.0);
  for (std::size_t j = 1; j < log.size(); ++j)
    screw[j] = screw[j - 1] + 0.5 * (log.screw_rpm[j] + log.screw_rpm[j - 1]) / 60.0 * 2 * std::numbers::pi *
                                  (log.t_s[j] - log.t_s[j - 1]);

  RunSeries out;
  SeriesData& d = out.data;
  d.y_unit = "mm3_s";
  d.dynamics.resize(basis.size());
  d.initial.resize(free.free.size());
  RotatingPart wheel{"wheel", {}}, screw_part{"screw", {}};
  std::vector<double> measured_height;
  std::vector<double> latency;
  for (std::size_t k = 0; k < flow.samples.size(); ++k) {
    const FlowSample& s = flow.samples[k];
    if (!s.valid || !std::isfinite(s.area_corrected_mm2) || s.area_corrected_mm2 <= 0.0) continue;
    const double t_k = profiles.t_s[k];
    const double p_k = UnwrapNear(profiles.encoder[k], rig.encoder, st->finder->PositionAt(t_k));
    out.profile.push_back(k);
    st->start.push_back(st->finder->StartAt(t_k));
    st->counts_measured.push_back(p_k);
    st->area.push_back(s.area_corrected_mm2);
    d.t.push_back(s.t_s);
    d.u.push_back(s.screw_rpm);
    d.y.push_back(s.flow_mm3_s);
    d.base.push_back(InterpolateLinear(st->log_t, st->model_flow, s.t_s));
    for (std::size_t b = 0; b < basis.size(); ++b)
      d.dynamics[b].push_back(InterpolateLinear(st->log_t, basis[b], s.t_s));
    for (std::size_t b = 0; b < free.free.size(); ++b)
      d.initial[b].push_back(InterpolateLinear(st->log_t, free.free[b], s.t_s));
    wheel.angle_rad.push_back(CountsToAngleRad(p_k - rig.offset_counts, rig.encoder));
    screw_part.angle_rad.push_back(InterpolateLinear(log.t_s, screw, s.t_s));
    d.time_to_laser_s.push_back(t_k - s.t_s);
    measured_height.push_back(geometry[k].height_mm);
    // When did the log's encoder read this profile's count?
    const double t_at = st->finder->Find(t_k + 1.0, p_k);
    if (std::isfinite(t_at)) latency.push_back(t_k - t_at);
  }
  d.parts = {wheel, screw_part};
  for (const LogChannel& c : log.channels) d.channels.push_back({c.name, c.unit, log.t_s, c.values});
  // The height the model implies, not the one measured: a measured height
  // carries the measured flow's own deviations, and a term in it would
  // explain the output by itself. The run's own height-area relation
  // (height = c sqrt(area), c the median ratio) applied to the model's area
  // (its flow over the surface speed).
  {
    std::vector<double> ratio;
    for (std::size_t i = 0; i < measured_height.size(); ++i)
      if (st->area[i] > 0 && measured_height[i] > 0) ratio.push_back(measured_height[i] / std::sqrt(st->area[i]));
    const double c = ratio.empty() ? 0.0 : MedianInPlace(ratio.data(), ratio.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double v = InterpolateLinear(st->log_t, st->speed, d.t[i]);
      d.height_mm.push_back(c * std::sqrt(std::max(d.base[i], 0.0) / std::max(v, 1e-9)));
    }
  }
  if (!latency.empty()) {
    std::vector<double> dev(latency.size());
    const double med = MedianInPlace(latency.data(), latency.size());
    for (std::size_t i = 0; i < dev.size(); ++i) dev[i] = std::abs(latency[i] - med);
    const double sigma = 1.4826 * MedianInPlace(dev.data(), dev.size());
    out.timestamp_offset_s = med;
    // The median's standard error is 1.2533 sigma / sqrt(n) for normal scatter.
    out.timestamp_offset_ci95_s = 1.96 * 1.2533 * sigma / std::sqrt(static_cast<double>(latency.size()));
  }
  d.shifted = [st](double counts, const std::vector<double>& extra_delay, std::vector<double>& y,
                   std::vector<double>& base) {
    const std::size_t n = st->start.size();
    y.resize(n);
    base.resize(n);
    std::size_t at_speed = 0, at_model = 0;  // the extrusion times run nearly in order: searches start at the last
    for (std::size_t i = 0; i < n; ++i) {
      const double t_e = st->finder->Find(st->start[i], st->counts_measured[i] - st->offset - counts);
      if (!std::isfinite(t_e)) {
        y[i] = base[i] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      y[i] = InterpolateLinearNear(st->log_t, st->speed, t_e, at_speed) * st->area[i];
      base[i] = InterpolateLinearNear(st->log_t, st->model_flow, t_e - (extra_delay.empty() ? 0.0 : extra_delay[i]),
                                      at_model);
    }
  };
  return out;
}

}  // namespace bead::explain
