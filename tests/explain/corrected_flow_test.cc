// The corrected flow on the twin (explain/corrected_flow.h): for each
// effect that acts on the measurement (a stale offset, a dwell shrink, an
// eccentric wheel), where explain finds it the corrected flow is written
// and lies closer to the twin's true flow than the flow it corrects.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "libbead/explain/corrected_flow.h"
#include "tests/explain/twin_runs.h"

namespace bead::explain {
namespace {

using namespace twin;

// A stale offset in the rig file, on a warm run: found, the run's offset
// within its finite interval of the truth, and the corrected flow (the
// offset re-aligned) closer to the twin's true flow than the flow the rig
// file gave.
TEST(ExplainWarmRun, FindsAStaleOffsetAndItsCorrectedFlowIsCloserToTheTruth) {
  sim::SimConfig c = Warm(22);
  c.effects.rig_offset_error_counts = 400.0;
  const Outcome o = ExplainRun(c);
  ASSERT_TRUE(o.report.position_shift_estimated);
  const Rig& rig = o.run->sim.rig_file;
  const double true_offset = o.run->sim.truth.offset_counts;
  const ShiftProfile& p = o.report.shift_profile;
  EXPECT_FALSE(p.lo_at_edge || p.hi_at_edge);
  EXPECT_LE(rig.offset_counts + p.lo, true_offset);
  EXPECT_GE(rig.offset_counts + p.hi, true_offset);
  EXPECT_LT(p.hi, 0.0) << "the rig file's offset must lie outside the run's interval";
  const CorrectedFlow cf = CorrectFlow(rig, o.run->sim.run.profiles, o.run->geometry, *o.run->sim.run.log, {}, {},
                                       o.report, CalibrationModel().tf, CalibrationModel().offset);
  // Against the truth (the flow laid, at each sample's extrusion time).
  const auto& truth = o.run->sim.truth.flow;
  auto rms = [&](const FlowResult& f) {
    double s = 0;
    int n = 0;
    for (const auto& x : f.samples)
      if (x.valid && std::isfinite(x.t_s) && std::isfinite(x.flow_mm3_s)) {
        const double q = InterpolateLinear(truth.t_s, truth.flow_mm3_s, x.t_s);
        s += (x.flow_mm3_s - q) * (x.flow_mm3_s - q), ++n;
      }
    return std::sqrt(s / n);
  };
  const double before = rms(o.run->flow), after = rms(cf.flow);
  std::printf(
      "warm, stale offset: interval %.1f..%.1f (true %.1f); flow RMS against the truth %.1f -> %.1f mm^3/s; "
      "against the model %.1f -> %.1f\n",
      rig.offset_counts + p.lo, rig.offset_counts + p.hi, true_offset, before, after, cf.rms_before, cf.rms_after);
  EXPECT_LT(after, before);
  EXPECT_LT(cf.rms_after, cf.rms_before);
}

// The dwell-time shrink: 10 % with a time constant of 1.2 s, the
// wheel stepped +-25 % on its own, a minute at 128 points, on three seeds.
// Its constant part is a gain the run cannot tell from the base model's,
// so the corrected flow undoes only its change with the time to the laser:
// where it is written, it must lie closer to the truth than the
// uncorrected flow once each takes its best constant gain, and what it
// undoes must not reach the constant (the mean moves by less than the
// shrink's spread over the run). The shrink is found on two of the three
// (on the third it fails the held-out test and nothing is added); at
// least one must find it.
TEST(ExplainWarmRun, ADwellShrinkIsUndoneOnlyInWhatTheRunIdentifies) {
  int found = 0;
  for (uint64_t seed : {31, 32, 33}) {
    sim::SimConfig c = Warm(seed);
    c.duration_s = 60.0;
    c.sensor.points = 128;
    c.wheel.cmd_levels_v = {6.0, 4.5, 7.5, 6.0, 4.5, 7.5};
    c.wheel.cmd_durations_s = {10.0, 10.0, 10.0, 10.0, 10.0, 10.0};
    c.effects.shrink_frac = 0.10;
    c.effects.shrink_tau_s = 1.2;
    const Outcome o = ExplainRun(c);
    if (!Find(o.report, "cooling_shrink")) continue;
    ++found;
    const Rig& rig = o.run->sim.rig_file;
    const CorrectedFlow cf = CorrectFlow(rig, o.run->sim.run.profiles, o.run->geometry, *o.run->sim.run.log, {}, {},
                                         o.report, CalibrationModel().tf, CalibrationModel().offset);
    if (!cf.lowers_error) continue;  // not written: nothing to hold against the truth
    const AgainstTruth before = Against(o.run->flow, o.run->sim.truth.flow);
    const AgainstTruth after = Against(cf.flow, o.run->sim.truth.flow);
    // The shrink's spread over the run: 10 % times the spread of 1 - exp(-dt / 1.2).
    double lo = 1, hi = 0;
    for (double dt : o.series.data.time_to_laser_s) {
      const double f = 1 - std::exp(-dt / 1.2);
      lo = std::min(lo, f), hi = std::max(hi, f);
    }
    std::printf(
        "seed %d, dwell shrink: at the best gain (%.4f, %.4f) RMS against the truth %.2f -> %.2f mm^3/s; mean "
        "%.1f -> %.1f mm^3/s; the shrink spans %.2f %% of the flow\n",
        static_cast<int>(seed), before.gain, after.gain, before.rms_at_gain, after.rms_at_gain, before.mean, after.mean,
        100 * 0.10 * (hi - lo));
    EXPECT_LT(after.rms_at_gain, before.rms_at_gain) << "seed " << seed;
    EXPECT_LT(std::abs(after.mean - before.mean), 0.10 * (hi - lo) * before.mean) << "seed " << seed;
  }
  EXPECT_GE(found, 1);
}
// The eccentric wheel: 2 mm on a 254.8-mm wheel, so the surface
// under the nozzle runs +-1.6 % off the encoder's speed once a revolution.
// explain finds the once-per-revolution term; the corrected flow divides
// the speed by it. The held-out comparison must see that (it refits the
// base's delay through the series' shift hook, which rebuilt the flow from
// the log's speed and so never saw a speed correction: 66.39 -> 66.39
// mm^3/s on the run), so the corrected flow is written, and it
// lies closer to the truth than the flow it corrects, at the flows' own
// gain (the term has no constant part to move it).
TEST(ExplainWarmRun, AnEccentricWheelsCorrectedFlowIsWrittenAndCloserToTheTruth) {
  int found = 0;
  for (uint64_t seed : {41, 42}) {
    sim::SimConfig c = Warm(seed);
    c.duration_s = 60.0;
    c.sensor.points = 128;
    c.wheel.cmd_levels_v = {6.0, 4.5, 7.5, 6.0, 4.5, 7.5};
    c.wheel.cmd_durations_s = {10.0, 10.0, 10.0, 10.0, 10.0, 10.0};
    c.effects.eccentricity_mm = 2.0;
    const Outcome o = ExplainRun(c);
    if (!Find(o.report, "once_per_rev[wheel]")) continue;
    ++found;
    const Rig& rig = o.run->sim.rig_file;
    const CorrectedFlow cf = CorrectFlow(rig, o.run->sim.run.profiles, o.run->geometry, *o.run->sim.run.log, {}, {},
                                         o.report, CalibrationModel().tf, CalibrationModel().offset);
    const AgainstTruth before = Against(o.run->flow, o.run->sim.truth.flow);
    const AgainstTruth after = Against(cf.flow, o.run->sim.truth.flow);
    std::printf(
        "seed %d, eccentric wheel: held-out RMS against the model %.2f -> %.2f mm^3/s (written: %d); at the best "
        "gain RMS against the truth %.2f -> %.2f mm^3/s\n",
        static_cast<int>(seed), cf.rms_before, cf.rms_after, cf.lowers_error, before.rms_at_gain, after.rms_at_gain);
    EXPECT_TRUE(cf.lowers_error) << "seed " << seed << ": " << cf.why_not;
    EXPECT_LT(after.rms_at_gain, before.rms_at_gain) << "seed " << seed;
  }
  EXPECT_GE(found, 1);
}

}  // namespace
}  // namespace bead::explain
