#include "libbead/explain/run_explain.h"

#include <algorithm>
#include <cmath>

#include "libbead/core/error.h"

namespace bead::explain {
namespace {

RunSeries SeriesOf(const Rig& rig, const MeasuredFlow& m, const model::TransferFunction& tf, double offset,
                   const RunExplainOptions& o) {
  RunSeries s = MakeRunSeries(rig, *m.profiles, *m.geometry, *m.log, *m.flow, tf, offset, {},
                              o.profiles_per_sample ? o.profiles_per_sample : ExplainBinOf(*m.flow));
  SelectChannels(s.data.channels, o.channels, o.no_channels, m.path);
  return s;
}

OffsetFromRun OffsetOf(const Rig& rig, const ExplainReport& r) {
  OffsetFromRun o;
  o.estimated = r.position_shift_estimated;
  if (!o.estimated) return o;
  const ShiftProfile& p = r.shift_profile;
  o.counts = rig.offset_counts + r.position_shift_counts;
  o.lo_counts = rig.offset_counts + p.lo;
  o.hi_counts = rig.offset_counts + p.hi;
  o.ci95_counts = r.position_shift_ci95_counts;
  o.pinned = !(p.lo_at_edge || p.hi_at_edge);
  o.excludes_rig = o.pinned && (p.lo > 0 || p.hi < 0);
  o.delay_correlation = r.shift_delay_correlation;
  return o;
}

}  // namespace

std::size_t ExplainBinOf(const FlowResult& flow) {
  std::size_t n = 0;
  double lo = INFINITY, hi = -INFINITY;
  for (const FlowSample& s : flow.samples)
    if (s.valid && std::isfinite(s.t_s)) ++n, lo = std::min(lo, s.t_s), hi = std::max(hi, s.t_s);
  return n < 2 ? 1 : ExplainBin(n, hi - lo);
}

void SelectChannels(std::vector<Channel>& channels, const std::vector<std::string>& names, bool none,
                    const std::string& path) {
  if (none) {
    channels.clear();
    return;
  }
  if (names.empty()) return;
  std::vector<Channel> kept;
  for (const std::string& n : names) {
    const auto it = std::find_if(channels.begin(), channels.end(), [&](const Channel& c) { return c.name == n; });
    if (it == channels.end()) {
      std::string have;
      for (const auto& c : channels) have += (have.empty() ? "" : ", ") + c.name;
      throw Error(
          Located(path, "/log/" + n, "no such recorded channel (the log has: " + (have.empty() ? "none" : have) + ")"));
    }
    kept.push_back(*it);
  }
  channels = kept;
}

RunExplanation ExplainMeasuredRun(const Rig& rig, const MeasuredFlow& run, const MeasuredFlow* held_out,
                                  const model::TransferFunction& model, double model_offset,
                                  const RunExplainOptions& o) {
  RunExplanation out;
  out.aligned_at_counts = rig.offset_counts;
  out.series = SeriesOf(rig, run, model, model_offset, o);
  ExplainOptions options = o.explain;
  std::optional<RunSeries> other;
  if (held_out) {
    other = SeriesOf(rig, *held_out, model, model_offset, o);
    if (other->data.channels.size() != out.series.data.channels.size())
      throw Error(Located(
          held_out->path, "/log",
          "does not record the same channels as " + run.path + " (name them with --channels, or --no-channels)"));
    options.validation = &other->data;
  }
  options.catalogue.has_wheel = true;
  options.catalogue.position_range_counts = rig.encoder.counts_per_rev / 20.0;
  out.report = Explain(out.series.data, options);
  out.offset = OffsetOf(rig, out.report);
  if (o.correct_flow)
    out.corrected = CorrectFlow(rig, *run.profiles, *run.geometry, *run.log, run.CorrectedArea(), run.CorrectedSigma(),
                                out.report, model, model_offset);
  return out;
}

OffsetComparison CompareOffsets(const OffsetFromRun& run, double pins_counts, double pins_ci95_counts) {
  OffsetComparison c;
  c.pins_counts = pins_counts;
  c.pins_ci95_counts = pins_ci95_counts;
  c.difference = run.counts - pins_counts;
  const double run_sd = run.ci95_counts / 1.96, pin_sd = pins_ci95_counts / 1.96;
  c.run_pinned = run.pinned && std::isfinite(run_sd) && run_sd > 0;
  if (!c.run_pinned || !(pin_sd > 0)) return c;
  c.agree = std::abs(c.difference) <= 1.96 * std::hypot(run_sd, pin_sd);
  if (!c.agree) return c;
  const double w_run = 1 / (run_sd * run_sd), w_pin = 1 / (pin_sd * pin_sd);
  c.combined_counts = (w_run * run.counts + w_pin * pins_counts) / (w_run + w_pin);
  c.combined_ci95_counts = 1.96 / std::sqrt(w_run + w_pin);
  return c;
}

}  // namespace bead::explain
