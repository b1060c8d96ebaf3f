#include "libbead/explain/run_series.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  // The last shift's extrusion times and flow (the hook's memo).
  double memo_counts = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> memo_t, memo_y;
};

// The height the model implies, not the one measured: a measured height
// carries the measured flow's own deviations, and a term in it would
// explain the output by itself. The run's own height-area relation
// (height = c sqrt(area), c the median ratio) applied to the model's area
// (its flow over the surface speed).
std::vector<double> ModelHeight(const RunState& st, const SeriesData& d, const std::vector<double>& measured_height) {
  std::vector<double> ratio, out;
  for (std::size_t i = 0; i < measured_height.size(); ++i)
    if (st.area[i] > 0 && measured_height[i] > 0) ratio.push_back(measured_height[i] / std::sqrt(st.area[i]));
  const double c = ratio.empty() ? 0.0 : MedianInPlace(ratio.data(), ratio.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double v = InterpolateLinear(st.log_t, st.speed, d.t[i]);
    out.push_back(c * std::sqrt(std::max(d.base[i], 0.0) / std::max(v, 1e-9)));
  }
  return out;
}

// The profiles' time stamps against the log: the median latency, its 95 %
// interval from the median's standard error, 1.2533 sigma / sqrt(n) for
// normal scatter (sigma from the median absolute deviation).
void TimestampOffset(std::vector<double> latency, RunSeries& out) {
  if (latency.empty()) return;
  std::vector<double> dev(latency.size());
  const double med = MedianInPlace(latency.data(), latency.size());
  for (std::size_t i = 0; i < dev.size(); ++i) dev[i] = std::abs(latency[i] - med);
  const double sigma = 1.4826 * MedianInPlace(dev.data(), dev.size());
  out.timestamp_offset_s = med;
  out.timestamp_offset_ci95_s = 1.96 * 1.2533 * sigma / std::sqrt(static_cast<double>(latency.size()));
}

// y and base with the extrusion times moved by `counts` of wheel position
// and the model's input delayed by extra_delay_s[i] more.
std::function<void(double, const std::vector<double>&, std::vector<double>&, std::vector<double>&)> ShiftHook(
    std::shared_ptr<RunState> st) {
  return [st](double counts, const std::vector<double>& extra_delay, std::vector<double>& y,
              std::vector<double>& base) {
    const std::size_t n = st->start.size();
    // The extrusion times and the flow there depend on the shift only: a
    // fit that moves the delay alone (the offset profile refits it at each
    // trial offset) re-reads the model, not the log's positions.
    if (!(st->memo_counts == counts) || st->memo_t.size() != n) {
      st->memo_t.resize(n);
      st->memo_y.resize(n);
      std::size_t at_speed = 0;  // the extrusion times run nearly in order: searches start at the last
      for (std::size_t i = 0; i < n; ++i) {
        const double t_e = st->finder->Find(st->start[i], st->counts_measured[i] - st->offset - counts);
        st->memo_t[i] = t_e;
        st->memo_y[i] = std::isfinite(t_e) ? InterpolateLinearNear(st->log_t, st->speed, t_e, at_speed) * st->area[i]
                                           : std::numeric_limits<double>::quiet_NaN();
      }
      st->memo_counts = counts;
    }
    y = st->memo_y;
    base.resize(n);
    std::size_t at_model = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double t_e = st->memo_t[i];
      base[i] = std::isfinite(t_e) ? InterpolateLinearNear(st->log_t, st->model_flow,
                                                           t_e - (extra_delay.empty() ? 0.0 : extra_delay[i]), at_model)
                                   : std::numeric_limits<double>::quiet_NaN();
    }
  };
}

}  // namespace

RunSeries MakeRunSeries(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                        const AcquisitionLog& log, const FlowResult& flow, const model::TransferFunction& tf,
                        double model_offset, const FlowOptions& flow_options, std::size_t bin) {
  auto st = std::make_shared<RunState>();
  st->log_t = log.t_s;
  st->log_counts = UnwrapEncoder(log.encoder, rig.encoder, log.t_s).counts;
  st->speed = SurfaceSpeed(rig, st->log_t, st->log_counts, flow_options);
  st->model_flow = model::Predict(tf, model_offset, log.t_s, log.screw_rpm, {});
  const std::vector<double> den = tf.Monic().den;
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
  // Each valid profile, then its bin's means (bin 1: the profile itself).
  std::vector<std::size_t> valid;
  for (std::size_t k = 0; k < flow.samples.size(); ++k) {
    const FlowSample& s = flow.samples[k];
    if (s.valid && std::isfinite(s.area_corrected_mm2) && s.area_corrected_mm2 > 0.0) valid.push_back(k);
  }
  bin = std::max<std::size_t>(bin, 1);
  for (std::size_t first = 0; first + bin <= valid.size(); first += bin) {
    double t_prof = 0, counts = 0, area = 0, height = 0;
    for (std::size_t j = first; j < first + bin; ++j) {
      const std::size_t k = valid[j];
      const double t_k = profiles.t_s[k];
      const double p_k = UnwrapNear(profiles.encoder[k], rig.encoder, st->finder->PositionAt(t_k));
      t_prof += t_k / static_cast<double>(bin);
      counts += p_k / static_cast<double>(bin);
      area += flow.samples[k].area_corrected_mm2 / static_cast<double>(bin);
      height += geometry[k].height_mm / static_cast<double>(bin);
      // When did the log's encoder read this profile's count?
      const double t_at = st->finder->Find(t_k + 1.0, p_k);
      if (std::isfinite(t_at)) latency.push_back(t_k - t_at);
    }
    const std::size_t last = valid[first + bin - 1];
    const ExtrusionTimeFinder::Start start = st->finder->StartAt(profiles.t_s[last]);
    // A bin's extrusion time: where its mean count left the nozzle (the
    // same search the shift hook makes), its flow the speed there times its
    // mean area.
    const FlowSample& one = flow.samples[last];
    const double t_e = bin == 1 ? one.t_s : st->finder->Find(start, counts - rig.offset_counts);
    if (!std::isfinite(t_e)) continue;
    out.profile.push_back(valid[first + bin / 2]);
    st->start.push_back(start);
    st->counts_measured.push_back(counts);
    st->area.push_back(area);
    d.t.push_back(t_e);
    d.u.push_back(bin == 1 ? one.screw_rpm : InterpolateLinear(st->log_t, log.screw_rpm, t_e));
    d.y.push_back(bin == 1 ? one.flow_mm3_s : InterpolateLinear(st->log_t, st->speed, t_e) * area);
    d.base.push_back(InterpolateLinear(st->log_t, st->model_flow, t_e));
    for (std::size_t b = 0; b < basis.size(); ++b) d.dynamics[b].push_back(InterpolateLinear(st->log_t, basis[b], t_e));
    for (std::size_t b = 0; b < free.free.size(); ++b)
      d.initial[b].push_back(InterpolateLinear(st->log_t, free.free[b], t_e));
    wheel.angle_rad.push_back(CountsToAngleRad(counts - rig.offset_counts, rig.encoder));
    screw_part.angle_rad.push_back(InterpolateLinear(log.t_s, screw, t_e));
    d.time_to_laser_s.push_back(t_prof - t_e);
    measured_height.push_back(height);
  }
  d.parts = {wheel, screw_part};

  for (const LogChannel& c : log.channels) d.channels.push_back({c.name, c.unit, log.t_s, c.values});
  d.height_mm = ModelHeight(*st, d, measured_height);
  TimestampOffset(latency, out);
  d.shifted = ShiftHook(st);
  return out;
}

std::size_t ExplainBin(std::size_t samples, double duration_s) {
  constexpr std::size_t kMaxSamples = 16384;
  constexpr double kMinRateHz = 25.0;
  if (samples <= kMaxSamples || !(duration_s > 0)) return 1;
  const std::size_t for_count = (samples + kMaxSamples - 1) / kMaxSamples;
  const auto for_rate = static_cast<std::size_t>(std::floor(static_cast<double>(samples) / duration_s / kMinRateHz));
  return std::max<std::size_t>(1, std::min(for_count, for_rate));
}

std::vector<double> AverageInBins(const std::vector<double>& v, std::size_t bin) {
  bin = std::max<std::size_t>(bin, 1);
  std::vector<double> out;
  for (std::size_t first = 0; first + bin <= v.size(); first += bin) {
    double m = 0;
    for (std::size_t j = first; j < first + bin; ++j) m += v[j] / static_cast<double>(bin);
    out.push_back(m);
  }
  return out;
}

BinnedFlow BinValidFlow(const FlowResult& flow, std::size_t bin) {
  BinnedFlow b;
  for (const FlowSample& s : flow.samples)
    if (s.valid) b.t.push_back(s.t_s), b.u.push_back(s.screw_rpm), b.y.push_back(s.flow_mm3_s);
  b.t = AverageInBins(b.t, bin), b.u = AverageInBins(b.u, bin), b.y = AverageInBins(b.y, bin);
  return b;
}

}  // namespace bead::explain
