#include "libbead/explain/corrected_flow.h"

#include <cmath>

#include "libbead/explain/effect_fit.h"
#include "libbead/explain/run_series.h"

namespace bead::explain {
namespace {

// The model refitted (its gain, operating point, delay, initial state and
// the process's own effects) to this flow, and the RMS left.
double RmsAgainst(const SeriesData& d, EffectSet base) {
  std::vector<std::size_t> all(d.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  Refine(d, base, all);
  std::vector<double> y, pred;
  Evaluate(d, base, y, pred);
  double s = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (std::isfinite(y[i]) && std::isfinite(pred[i])) s += (y[i] - pred[i]) * (y[i] - pred[i]), ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : NAN;
}

}  // namespace

bool ActsOnMeasurement(const Effect& e) {
  if (e.kind == Effect::Kind::kPositionShift) return true;
  if (e.part >= 0) return e.tracks == "wheel";
  return e.feature == "time_to_laser" || e.feature == "height";
}

CorrectedFlow CorrectFlow(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                          const AcquisitionLog& log, const std::vector<double>& corrected_area,
                          const std::vector<double>& corrected_sigma, const ExplainReport& report,
                          const model::TransferFunction& model, double model_offset) {
  CorrectedFlow out;
  EffectSet base, kept;
  double shift = 0.0;
  for (std::size_t k = 0; k < report.final_effects.size(); ++k) {
    Active a{report.final_effects[k], report.final_params[k]};
    if (k < report.base_terms || !ActsOnMeasurement(a.effect)) {
      base.push_back(a);  // the model: the base refitted and the process's own effects
    } else {
      out.undone.push_back(a.effect.name);
      if (a.effect.kind == Effect::Kind::kPositionShift)
        shift += a.params[0];
      else
        kept.push_back(a);
    }
  }
  // The offset: where the run's own profile excludes the rig file's offset
  // (0 outside its 95 % interval, neither end at the searched range), the
  // profile's best, whether or not the held-out test kept the effect.
  const ShiftProfile& sp = report.shift_profile;
  if (shift == 0.0 && report.position_shift_estimated && !sp.lo_at_edge && !sp.hi_at_edge && (sp.lo > 0 || sp.hi < 0)) {
    shift = sp.best;
    out.undone.push_back("encoder_offset (the run's profile excludes the rig file's)");
  }
  const FlowResult before = ComputeFlow(rig, profiles, geometry, log, {}, corrected_area, corrected_sigma);
  const RunSeries series_before = MakeRunSeries(rig, profiles, geometry, log, before, model, model_offset);
  out.rms_before = RmsAgainst(series_before.data, base);
  Rig aligned = rig;
  aligned.offset_counts += shift;
  out.offset_counts = aligned.offset_counts;
  out.flow = shift != 0.0 ? ComputeFlow(aligned, profiles, geometry, log, {}, corrected_area, corrected_sigma) : before;
  RunSeries series = MakeRunSeries(aligned, profiles, geometry, log, out.flow, model, model_offset);
  // Each kept term's factor at each sample of the realigned flow.
  const SeriesData& d = series.data;
  for (std::size_t i = 0; i < d.size(); ++i) {
    double speed = 1.0, area = 1.0;
    for (const Active& a : kept) {
      const auto cols = a.effect.Columns(d, a.params.data());
      double term = 0.0;
      for (std::size_t j = 0; j < cols.size(); ++j) term += a.params[a.nl() + j] * cols[j][i];
      (a.effect.part >= 0 ? speed : area) *= 1.0 + term;
    }
    FlowSample& s = out.flow.samples[series.profile[i]];
    if (!(speed > 0) || !(area > 0)) continue;
    s.surface_speed_mm_s /= speed;
    s.area_corrected_mm2 /= area;
    s.flow_mm3_s /= speed * area;
    s.flow_sigma_mm3_s /= speed * area;
  }
  const RunSeries series_after = MakeRunSeries(aligned, profiles, geometry, log, out.flow, model, model_offset);
  out.rms_after = RmsAgainst(series_after.data, base);
  // The volume from the corrected flow, as ComputeFlow integrates it.
  double volume = 0.0, last_t = NAN, last_q = NAN;
  for (const FlowSample& s : out.flow.samples) {
    if (!s.valid || !std::isfinite(s.t_s) || !std::isfinite(s.flow_mm3_s)) continue;
    if (std::isfinite(last_t) && s.t_s > last_t) volume += 0.5 * (s.flow_mm3_s + last_q) * (s.t_s - last_t);
    if (!std::isfinite(last_t) || s.t_s > last_t) last_t = s.t_s, last_q = s.flow_mm3_s;
  }
  out.flow.total_volume_mm3 = volume;
  return out;
}

}  // namespace bead::explain
