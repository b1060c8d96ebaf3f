#include <cmath>
#include <cstdio>

#include "libbead/io/atomic_file.h"
#include "libbead/core/error.h"
#include "tools/explain_modes.h"

namespace bead::tools {

explain::ExplainOptions ExplainArgs::Explain() const {
  explain::ExplainOptions o;
  o.alpha = alpha;
  o.max_effects = max_effects;
  return o;
}

model::IdentifyOptions ExplainArgs::Identify() const {
  model::IdentifyOptions id;
  id.poles = poles;
  id.zeros = std::min(zeros, poles);
  model::SetStructure(structure, id);
  id.max_delay_s = max_delay_s;
  return id;
}

namespace {

// The identified model, as the terminal says it; `how`: where it was fitted.
void SayModel(const explain::BaseModel& m, const char* how) {
  std::printf("model identified: fit %.2f %%, delay", m.fit_percent);
  for (const auto& tf : m.tfs) std::printf(" %.3f", tf.delay_s);
  std::printf(" s%s\n", how);
  for (const std::string& w : m.warnings) std::printf("warning: %s\n", w.c_str());
}

}  // namespace

explain::BaseModel ModelFor(const ExplainArgs& a, const std::vector<double>& t,
                            const std::vector<std::vector<double>>& u, const std::vector<double>& y,
                            const std::vector<Segment>& segments, const std::string& where) {
  if (!a.model.empty()) return explain::BaseModelFromFile(a.model, u.size());
  const explain::BaseModel m = explain::IdentifyBaseModel(t, u, y, segments, a.Identify(), where);
  SayModel(m, "");
  return m;
}

explain::IdentifiedRun ExplainWithModel(const ExplainArgs& a, const Rig& rig, const explain::MeasuredFlow& run,
                                        const explain::MeasuredFlow* held_out,
                                        const explain::RunExplainOptions& options) {
  explain::IdentifiedRun out;
  if (!a.model.empty()) {
    out.model = explain::BaseModelFromFile(a.model, 1);
    out.explanation = explain::ExplainMeasuredRun(rig, run, held_out, out.model.tfs[0], out.model.offset, options);
    return out;
  }
  out = explain::ExplainIdentifiedRun(rig, run, held_out, a.Identify(), options);
  for (double at : out.realigned_at)
    std::printf(
        "the run's offset (%.1f counts) lies more than half its interval from the one the flow was aligned at: "
        "the model identified again on the flow aligned there (a model fitted on misaligned flow pulls the "
        "offset toward where it was fitted, and widens its interval)\n",
        at);
  SayModel(out.model, out.realigned_at.empty() ? "" : " (on the realigned flow)");
  if (out.reidentified && out.reidentified->ok) {
    const explain::ReidentifiedProfile& r = *out.reidentified;
    std::printf(
        "the offset profiled with the model identified again at each of %zu trial offsets: best %.1f counts, "
        "95 %% interval %.1f%s to %.1f%s (the interval printed below holds it)\n",
        r.counts.size(), r.best, r.lo, r.lo_at_edge ? " (search end)" : "", r.hi, r.hi_at_edge ? " (search end)" : "");
    if (r.scattered)
      std::printf(
          "that profile falls and rises again on one side of its least: identify settled in other delay basins "
          "at some trials, so it does not pin the offset\n");
  }
  return out;
}

void WriteJson(const std::string& path, const nlohmann::json& j) {
  AtomicFile file(path);
  file.stream() << j.dump(2) << "\n";
  file.Commit();
  std::printf("wrote %s\n", path.c_str());
}

void PrintReport(const explain::ExplainReport& r, const std::string& unit) {
  std::printf(
      "\nthe model as given (each stretch's initial state fitted): fit %.2f %%, RMS error %.4g %s; residual %s (chi2 "
      "%.1f, 99 %% limit %.1f), %s the input\n",
      r.before.fit_pct, r.before.rms, unit.c_str(), r.before.whiteness.white ? "white" : "not white",
      r.before.whiteness.chi2, r.before.whiteness.chi2_limit,
      r.before.input.independent ? "independent of" : "correlated with");
  std::string refit;
  for (const auto& e : r.base_refit)
    for (const auto& p : e.parameters) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %s = %.4g +- %.2g", refit.empty() ? " " : ", ", e.name.c_str(),
                    p.name.c_str(), p.value, p.ci95);
      refit += buf;
    }
  std::printf("base model refitted with every candidate:%s\n", refit.c_str());
  if (r.base.misspecified)
    std::printf(
        "warning: the base model's dynamics are misspecified: a linear correction of them lowers the held-out "
        "RMS %.4g -> %.4g (F %.1f > %.1f); re-identify it (more poles or zeros, another delay). Effects are "
        "only added beyond that correction.\n",
        r.base.rms_before, r.base.rms_after, r.base.heldout_f, r.base.threshold);
  std::printf("\n%-32s %-44s %9s %9s %11s %11s\n", "effect", "parameters (95 % interval)", "fit_bef_%", "fit_aft_%",
              "rms_before", "rms_after");
  if (r.effects_added.empty()) std::printf("%-32s\n", "(none added)");
  for (const auto& e : r.effects_added) {
    std::string params;
    for (const auto& p : e.parameters) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s=%.4g+-%.2g", params.empty() ? "" : ", ", p.name.c_str(), p.value, p.ci95);
      params += buf;
    }
    std::printf("%-32s %-44s %9.2f %9.2f %11.4g %11.4g\n", e.name.c_str(), params.c_str(), e.fit_before_pct,
                e.fit_after_pct, e.rms_before, e.rms_after);
  }
  std::printf("\nafter: fit %.2f %%, RMS error %.4g %s; residual %s (chi2 %.1f)\n", r.after.fit_pct, r.after.rms,
              unit.c_str(), r.after.whiteness.white ? "white" : "not white", r.after.whiteness.chi2);
  for (const auto& u : r.unexplained)
    std::printf("unexplained: %s, tracks %s (power %.1f, false alarm %.2g)\n", u.what.c_str(), u.tracks.c_str(),
                u.power, u.false_alarm);
  for (const auto& c : r.confounded)
    if (std::isfinite(c.correlation))
      std::printf("confounded: %s and %s trade (correlation %+.3f): %s\n", c.first.c_str(), c.second.c_str(),
                  c.correlation, c.note.c_str());
    else  // a pair told apart by something other than a correlation (the run's two halves)
      std::printf("confounded: %s and %s: %s\n", c.first.c_str(), c.second.c_str(), c.note.c_str());
}

void PrintRun(const explain::RunExplanation& e, const Rig& rig, const std::string& path, const std::string& validate) {
  for (const auto& c : e.series.data.channels)
    std::printf("recorded channel: %s (%s), tried as a cause\n", c.name.c_str(),
                c.unit.empty() ? "no unit" : c.unit.c_str());
  if (!validate.empty()) std::printf("held-out data: %s\n", validate.c_str());
  std::printf("%s: %zu samples of flow in extrusion time\n", path.c_str(), e.series.data.size());
  PrintReport(e.report, "mm^3/s");
  const explain::OffsetFromRun& o = e.offset;
  if (!o.pinned && e.report.shift_profile.speed_follows_input)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: the wheel's speed follows the extruder (%.0f %% of "
        "its changes are a filter of the model's input, as on a wheel fed forward from the extruder), so a "
        "position error looks like a change of the model's dynamics, and where the error is least (%.1f counts) "
        "is the model's misfit, not the offset (a run whose wheel changes speed on its own, or the pins, pin "
        "it); rig file: %.1f counts\n",
        100.0 * e.report.shift_profile.speed_input_share, o.counts, rig.offset_counts);
  else if (!o.pinned && e.report.shift_profile.steady_wheel)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: the wheel's speed changes too little to tell a "
        "position error from a time error (at a steady speed they are one: their signatures correlate at %.4f "
        "as this wheel's speed changes allow, beyond 0.99; %.3f in the joint fit at the delay identify took), so "
        "where the error is least (%.1f counts) is the model's misfit, not the offset (a run whose wheel changes "
        "speed by tens of percent, or the pins, pin it); rig file: %.1f counts\n",
        e.report.shift_profile.speed_delay_correlation, o.delay_correlation, o.counts, rig.offset_counts);
  else if (!o.pinned && e.report.shift_profile.inseparable)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: it trades with the delay (correlation %.3f): the "
        "wheel's speed changes too little, or only in step with the flow, to tell a position error from a time "
        "error, and where the error is least (%.1f counts) is the model's misfit, not the offset; rig file: %.1f "
        "counts\n",
        o.delay_correlation, o.counts, rig.offset_counts);
  else if (!o.pinned && o.scattered)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: with the model held it lies at %.1f counts, but "
        "with the model identified again at each trial offset the error falls and rises again (identify's "
        "delay basins, not the data, shape it), so the run cannot say which model's offset is right (the pins "
        "pin it); rig file: %.1f counts\n",
        o.counts, rig.offset_counts);
  else if (!o.pinned)
    std::printf(
        "encoder offset from the run: NOT pinned by this run: the error stays within the noise of its least "
        "(at %.1f counts) from %.1f to %.1f counts, out to the end of the range searched, so the run does not "
        "locate the offset (no interval: the wheel's speed changes too little, or only in step with the flow, "
        "to tell a position error from a time error, or the model's misfit moves the least); rig file: %.1f "
        "counts\n",
        o.counts, o.lo_counts, o.hi_counts, rig.offset_counts);
  else
    std::printf(
        "encoder offset from the run: %.1f counts, 95 %% interval %.1f to %.1f (the residual's colour and the "
        "delay refitted at every offset accounted for); rig file: %.1f counts%s\n",
        o.counts, o.lo_counts, o.hi_counts, rig.offset_counts, o.excludes_rig ? " -- OUTSIDE the run's interval" : "");
  std::printf("profile time stamps against the log: %+.4f +- %.4f s (a sensor latency shows here)\n",
              e.series.timestamp_offset_s, e.series.timestamp_offset_ci95_s);
}

void PrintPins(const explain::OffsetComparison& c, const explain::OffsetFromRun& run, const std::string& path) {
  if (!c.run_pinned) {
    std::printf("pin scans (%s): %.1f +- %.1f counts\n", path.c_str(), c.pins_counts, c.pins_ci95_counts);
    std::printf("offset: the run does not pin it; the pins' %.1f +- %.1f counts stands alone\n", c.pins_counts,
                c.pins_ci95_counts);
    return;
  }
  std::printf("pin scans (%s): %.1f +- %.1f counts; the run's offset differs by %+.1f counts\n", path.c_str(),
              c.pins_counts, c.pins_ci95_counts, c.difference);
  if (c.agree)
    std::printf("offset, run and pins combined: %.1f +- %.1f counts (they agree within their intervals)\n",
                c.combined_counts, c.combined_ci95_counts);
  else
    std::printf(
        "offset: the run (%.1f +- %.1f) and the pins (%.1f +- %.1f) DISAGREE by %.1f counts, more than their "
        "intervals allow: a pin placed off the nozzle's centre, a slipped encoder, or an effect the run's "
        "model lacks; they are not combined\n",
        run.counts, run.ci95_counts, c.pins_counts, c.pins_ci95_counts, c.difference);
}

void PrintCorrected(const explain::CorrectedFlow& cf, const std::string& path) {
  std::string undone;
  for (const auto& u : cf.undone) undone += (undone.empty() ? "" : ", ") + u;
  if (cf.lowers_error) {
    std::printf(
        "corrected flow: %s undone (offset %.1f counts); held-out RMS against the model %.4g -> %.4g mm^3/s; "
        "total volume %.1f mm^3\nwrote %s\n",
        undone.c_str(), cf.offset_counts, cf.rms_before, cf.rms_after, cf.flow.total_volume_mm3, path.c_str());
    return;
  }
  std::printf("corrected flow NOT written (%s): %s%s%s\n", path.c_str(), cf.why_not.c_str(),
              undone.empty() ? "" : "; tried: ", undone.c_str());
  if (!undone.empty())
    std::printf("  held-out RMS against the model %.4g -> %.4g mm^3/s\n", cf.rms_before, cf.rms_after);
}

}  // namespace bead::tools
