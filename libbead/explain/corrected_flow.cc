#include "libbead/explain/corrected_flow.h"

#include <cmath>

#include "libbead/explain/effect_fit.h"
#include "libbead/explain/run_series.h"

namespace bead::explain {
namespace {

// The model (the base refitted with the process's own effects) fitted on
// every other of 20 time blocks of this flow, its RMS on the blocks
// between: the held-out error a correction must lower.
double HeldOutRms(const SeriesData& d, EffectSet base) {
  std::vector<std::size_t> estimation, held_out;
  const double t0 = d.t.front(), span = std::max(d.t.back() - t0, 1e-9);
  for (std::size_t i = 0; i < d.size(); ++i)
    (static_cast<int>((d.t[i] - t0) / span * 20) % 2 == 0 ? estimation : held_out).push_back(i);
  Refine(d, base, estimation);
  std::vector<double> y, pred;
  Evaluate(d, base, y, pred);
  double s = 0;
  std::size_t n = 0;
  for (std::size_t i : held_out)
    if (std::isfinite(y[i]) && std::isfinite(pred[i])) s += (y[i] - pred[i]) * (y[i] - pred[i]), ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : NAN;
}

// A kept term's value at every sample, less its mean: the constant part of
// a multiplicative term is a gain, which the base model's refit takes and
// the run cannot tell from one, so it is never undone.
std::vector<double> VaryingTerm(const SeriesData& d, const Active& a) {
  const auto cols = a.effect.Columns(d, a.params.data());
  std::vector<double> term(d.size(), 0.0);
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (std::size_t i = 0; i < d.size(); ++i) term[i] += a.params[a.nl() + j] * cols[j][i];
  double mean = 0;
  for (double v : term) mean += v;
  mean /= static_cast<double>(std::max<std::size_t>(term.size(), 1));
  for (double& v : term) v -= mean;
  return term;
}

// The relative variance of the product of the kept terms' factors at each
// sample, from their parameters' covariance (numerical gradients).
std::vector<double> FactorVariance(const SeriesData& d, const std::vector<Active>& kept,
                                   const std::vector<std::size_t>& first_slot, const std::vector<double>& covariance) {
  const auto slots = static_cast<std::size_t>(std::llround(std::sqrt(static_cast<double>(covariance.size()))));
  std::vector<std::vector<double>> grad;  // [kept slot][sample]: d log(factor)
  std::vector<std::size_t> slot_of;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const std::vector<double> base_term = VaryingTerm(d, kept[k]);
    for (std::size_t p = 0; p < kept[k].params.size(); ++p) {
      Active moved = kept[k];
      const double h = 1e-6 * std::max(std::abs(moved.params[p]), 1e-3);
      moved.params[p] += h;
      const std::vector<double> t = VaryingTerm(d, moved);
      std::vector<double> g(d.size());
      for (std::size_t i = 0; i < d.size(); ++i) g[i] = (t[i] - base_term[i]) / h / (1.0 + base_term[i]);
      grad.push_back(std::move(g));
      slot_of.push_back(first_slot[k] + p);
    }
  }
  std::vector<double> var(d.size(), 0.0);
  for (std::size_t a = 0; a < grad.size(); ++a)
    for (std::size_t b = 0; b < grad.size(); ++b) {
      const double c = slots ? covariance[slot_of[a] * slots + slot_of[b]] : NAN;
      if (!std::isfinite(c)) continue;  // a parameter the data does not pin is not undone (see the caller)
      for (std::size_t i = 0; i < d.size(); ++i) var[i] += grad[a][i] * grad[b][i] * c;
    }
  return var;
}

// The series' shift hook recomputes the flow at a trial shift from the
// log's surface speed and the bins' areas (run_series.h): the area there is
// the corrected one, the speed is not. The held-out comparison refits the
// base's delay and offset through that hook, so without this it would
// compare the uncorrected speed again and never see a speed correction
// (an eccentric wheel's once-per-revolution term). Each sample's flow at a
// shift is divided by its speed factor, as the flow itself is.
void UndoSpeedInShifts(SeriesData& d, const std::vector<double>& speed) {
  if (!d.shifted) return;
  d.shifted = [inner = d.shifted, speed](double counts, const std::vector<double>& extra_delay_s,
                                         std::vector<double>& y, std::vector<double>& base) {
    inner(counts, extra_delay_s, y, base);
    for (std::size_t i = 0; i < y.size() && i < speed.size(); ++i)
      if (speed[i] > 0) y[i] /= speed[i];
  };
}

}  // namespace

MeasurementFactors FactorsOf(const SeriesData& d, const std::vector<Active>& kept,
                             const std::vector<std::size_t>& first_slot, const std::vector<double>& covariance) {
  MeasurementFactors f;
  f.speed.assign(d.size(), 1.0);
  f.area.assign(d.size(), 1.0);
  for (const Active& a : kept) {
    const std::vector<double> term = VaryingTerm(d, a);
    std::vector<double>& factor = a.effect.part >= 0 ? f.speed : f.area;
    for (std::size_t i = 0; i < d.size(); ++i) factor[i] *= 1.0 + term[i];
  }
  f.relative_variance = FactorVariance(d, kept, first_slot, covariance);
  return f;
}

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
  EffectSet base;
  std::vector<Active> kept;
  std::vector<std::size_t> kept_slot;  // each kept effect's first slot in the final covariance
  double shift = 0.0, shift_sd = 0.0;
  std::size_t slot = 0;
  for (std::size_t k = 0; k < report.final_effects.size(); ++k) {
    Active a{report.final_effects[k], report.final_params[k]};
    const std::size_t first = slot;
    slot += a.params.size();
    if (k < report.base_terms || !ActsOnMeasurement(a.effect)) {
      base.push_back(a);  // the model: the base refitted and the process's own effects
      continue;
    }
    out.undone.push_back(a.effect.name);
    if (a.effect.kind == Effect::Kind::kPositionShift) {
      shift += a.params[0];
      shift_sd = std::isfinite(report.position_shift_ci95_counts) ? report.position_shift_ci95_counts / 1.96 : 0.0;
    } else {
      kept.push_back(a);
      kept_slot.push_back(first);
    }
  }
  // The offset: where the run's own interval excludes the rig file's
  // offset (0 outside it, neither end at the searched range), the
  // profile's best, whether or not the held-out test kept the effect.
  const ShiftProfile& sp = report.shift_profile;
  if (shift == 0.0 && report.position_shift_estimated && !sp.lo_at_edge && !sp.hi_at_edge && (sp.lo > 0 || sp.hi < 0)) {
    shift = sp.best;
    shift_sd = std::isfinite(report.position_shift_ci95_counts) ? report.position_shift_ci95_counts / 1.96 : 0.0;
    out.undone.push_back("encoder_offset (the run's interval excludes the rig file's)");
  }
  const FlowResult before = ComputeFlow(rig, profiles, geometry, log, {}, corrected_area, corrected_sigma);
  const RunSeries series_before = MakeRunSeries(rig, profiles, geometry, log, before, model, model_offset);
  out.rms_before = HeldOutRms(series_before.data, base);
  Rig aligned = rig;
  aligned.offset_counts += shift;
  out.offset_counts = aligned.offset_counts;
  out.flow = shift != 0.0 ? ComputeFlow(aligned, profiles, geometry, log, {}, corrected_area, corrected_sigma) : before;
  RunSeries series = MakeRunSeries(aligned, profiles, geometry, log, out.flow, model, model_offset);
  const SeriesData& d = series.data;
  // The flow's change with the offset, for the offset's uncertainty.
  std::vector<double> y_plus, y_minus, unused;
  const double h = std::max(shift_sd, 0.5);
  if (shift_sd > 0 && d.shifted) d.shifted(h, {}, y_plus, unused), d.shifted(-h, {}, y_minus, unused);
  const MeasurementFactors factors = FactorsOf(d, kept, kept_slot, report.final_covariance);
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double speed = factors.speed[i], area = factors.area[i];
    FlowSample& s = out.flow.samples[series.profile[i]];
    if (!(speed > 0) || !(area > 0)) continue;
    s.surface_speed_mm_s /= speed;
    s.area_corrected_mm2 /= area;
    s.flow_mm3_s /= speed * area;
    // The sigma: the measurement's own, the factors' and the offset's.
    double var =
        std::pow(s.flow_sigma_mm3_s / (speed * area), 2) + s.flow_mm3_s * s.flow_mm3_s * factors.relative_variance[i];
    if (!y_plus.empty() && std::isfinite(y_plus[i]) && std::isfinite(y_minus[i]))
      var += std::pow((y_plus[i] - y_minus[i]) / (2 * h) * shift_sd, 2);
    s.flow_sigma_mm3_s = std::sqrt(var);
  }
  RunSeries series_after = MakeRunSeries(aligned, profiles, geometry, log, out.flow, model, model_offset);
  UndoSpeedInShifts(series_after.data, factors.speed);
  out.rms_after = HeldOutRms(series_after.data, base);
  out.lowers_error = !out.undone.empty() && out.rms_after < out.rms_before;
  if (out.undone.empty())
    out.why_not = "no kept effect acts on the measurement: there is nothing to undo";
  else if (!out.lowers_error)
    out.why_not = "undoing them does not lower the held-out error against the model";
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
