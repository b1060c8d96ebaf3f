#include "libbead/explain/confounding.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "libbead/explain/speed_follows_input.h"

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

// Pairs of parameters whose estimates correlate beyond 0.9, at least one
// of them an effect's (the base model's gain and operating point always
// trade a little, and say nothing).
std::vector<Confounding> Confounded(const EffectSet& set, const ParameterCovariance& cov, std::size_t base_terms) {
  std::vector<Confounding> out;
  const std::size_t P = cov.index.size();
  auto name = [&](std::size_t slot) {
    const Active& a = set[cov.index[slot].first];
    const std::size_t k = cov.index[slot].second;
    return a.effect.name + "." + (k < a.nl() ? a.effect.nonlinear[k] : a.effect.linear[k - a.nl()]);
  };
  for (std::size_t i = 0; i < P; ++i)
    for (std::size_t j = i + 1; j < P; ++j) {
      const std::size_t ei = cov.index[i].first, ej = cov.index[j].first;
      if (ei == ej || (ei < base_terms && ej < base_terms)) continue;
      const double r = cov.correlation[i * P + j];
      if (!(std::abs(r) > 0.9)) continue;
      const bool shrink = set[ei].effect.feature == "scale" && set[ej].effect.feature == "time_to_laser";
      out.push_back({name(i), name(j), r,
                     shrink ? "a constant shrink is a gain: only the shrink's change with the time to the laser is "
                              "in the data, and only that part is undone in a corrected flow"
                            : "the data pins their combination better than either: each interval is the one with "
                              "the other free"});
    }
  return out;
}

// What a fitted term adds to the prediction at each sample.
static std::vector<double> Contribution(const SeriesData& d, const Active& a) {
  const auto cols = a.effect.Columns(d, a.params.data());
  std::vector<double> out(d.size(), 0.0);
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (std::size_t i = 0; i < d.size(); ++i)
      out[i] += a.params[a.nl() + j] * cols[j][i] * (a.effect.kind == Effect::Kind::kMultiplicative ? d.base[i] : 1.0);
  return out;
}

static double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
  const double n = static_cast<double>(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  for (std::size_t i = 0; i < a.size(); ++i)
    saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb), sab += (a[i] - ma) * (b[i] - mb);
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : NAN;
}

// Two candidates that both passed in the round one of them was kept in,
// the other never added after it: the data cannot tell them apart when
// what they explain correlates.
void SayAlternative(const SeriesData& d, const Active& kept, const Active& alt, ExplainReport& report) {
  for (const AddedEffect& e : report.effects_added)
    if (e.name == alt.effect.name) return;  // added in a later round: told apart
  const double r = Correlation(Contribution(d, kept), Contribution(d, alt));
  if (!(std::abs(r) > 0.5)) return;
  report.confounded.push_back(
      {kept.effect.name, alt.effect.name, r,
       "both pass the held-out test alone and the second adds nothing beside the first: the data cannot tell "
       "these two causes apart (the one kept lowers the BIC more); a run that varies them apart can"});
}

namespace {

// Above this |correlation| of the offset with the delay the run cannot
// tell them apart (the variance inflation 1 / (1 - r^2) exceeds 10).
constexpr double kInseparable = 0.95;
// The same bar for the correlation the wheel's speed changes allow
// (speed_follows_input.h), set where a variance inflation reaches 50: that
// correlation leaves out the model's other terms and reads the speed's
// noise as changes, so it tells a steady wheel (0.9993-1.0000: the
// encoder's quantisation alone) from one that changes speed by a few
// percent (0.86-0.93 with +-20-25 % steps every 10 s), not more finely.
constexpr double kSteadyWheel = 0.99;
// Above this share of the wheel speed's variance following the model's
// input, the offset's signature is a change of the model's dynamics (the
// same 1 - R^2 < 0.1 rule: under a tenth of the speed's changes are its own).
constexpr double kFollowsInput = 0.9;

// The split-half check: the profile's best on the first and on the second
// half of the rows. Each half's best scatters sqrt(2) times the whole's
// standard deviation (sd, from the interval), their difference 2 sd; two
// halves further apart than 1.96 times that (the whole interval's width)
// say that something other than the noise sets the offset (a base model's
// misfit that happens to follow the wheel), and the interval is widened to
// hold the whole's best +- their difference and each half's own interval.
// A half lowest at the searched range's end leaves the offset not pinned.
void CheckHalves(const SeriesData& d, const EffectSet& current, const Effect& shift,
                 const std::vector<std::size_t>& rows, ShiftProfile& p) {
  const std::vector<double>& grid = shift.grid[0];
  const std::size_t h = rows.size() / 2;
  const std::vector<std::size_t> first(rows.begin(), rows.begin() + static_cast<long>(h)),
      second(rows.begin() + static_cast<long>(h), rows.end());
  p.first_half = ProfileShift(d, current, shift, first).best;
  p.second_half = ProfileShift(d, current, shift, second).best;
  const auto at_edge = [&](double b) { return b <= grid.front() || b >= grid.back(); };
  if (at_edge(p.first_half) || at_edge(p.second_half)) {
    p.halves_disagree = true;
    p.lo = grid.front(), p.hi = grid.back(), p.lo_at_edge = p.hi_at_edge = true;
    return;
  }
  const double diff = std::abs(p.first_half - p.second_half);
  if (diff <= p.hi - p.lo) return;
  p.halves_disagree = true;
  // Widened to hold the whole's best +- their difference and each half's
  // own interval (sqrt(2) times the whole's half-width about its best).
  const double w = std::sqrt(2.0) * 0.5 * (p.hi - p.lo);
  const double lo = std::min({p.lo, p.best - diff, std::min(p.first_half, p.second_half) - w});
  const double hi = std::max({p.hi, p.best + diff, std::max(p.first_half, p.second_half) + w});
  p.lo = std::max(grid.front(), lo);
  p.hi = std::min(grid.back(), hi);
  p.lo_at_edge |= p.lo <= grid.front();
  p.hi_at_edge |= p.hi >= grid.back();
}

}  // namespace

// The offset from the run: the profile, widened to the joint fit's
// interval at its best (the shift beside every other term) and by the
// split-half check, and the shift's correlation with the base model's
// delay.
void EstimateShift(const SeriesData& d, const EffectSet& current, const Effect& shift,
                   const std::vector<std::size_t>& rows, ExplainReport& report) {
  ShiftProfile& p = report.shift_profile;
  p = ProfileShift(d, current, shift, rows);
  EffectSet joint = p.refit_at_best;
  joint.push_back(Activate(shift));
  joint.back().params[0] = p.best;
  const ParameterCovariance jc = Covariance(d, joint, rows);
  const double sd = jc.sd.back()[0];
  ShiftInterval(p, jc.variance_along.back()[0]);
  const std::vector<double>& grid = shift.grid[0];
  // Not pinned: the joint fit cannot tell the shift, or the profile is
  // lowest at an end of the searched range (the data prefer an offset
  // outside it, or none; the range, +-counts_per_rev / 20, is arbitrary,
  // and an interval cut from it would be as arbitrary).
  if (!std::isfinite(sd) || p.best <= grid.front() || p.best >= grid.back()) {
    p.lo = grid.front(), p.hi = grid.back(), p.lo_at_edge = p.hi_at_edge = true;
  } else {
    if (p.best - 1.96 * sd < p.lo)
      p.lo = std::max(grid.front(), p.best - 1.96 * sd), p.lo_at_edge |= p.lo <= grid.front();
    if (p.best + 1.96 * sd > p.hi)
      p.hi = std::min(grid.back(), p.best + 1.96 * sd), p.hi_at_edge |= p.hi >= grid.back();
  }
  if (!(p.lo_at_edge || p.hi_at_edge)) CheckHalves(d, current, shift, rows, p);
  for (std::size_t e = 0; e + 1 < joint.size(); ++e)
    if (joint[e].effect.kind == Effect::Kind::kDelay)
      report.shift_delay_correlation = jc.Correlation(joint.size() - 1, 0, e, 0);
  // Inseparable from the delay: with |correlation| above kInseparable the
  // offset keeps under a tenth of its information once the delay is free
  // (1 - r^2 < 0.1); what is left is of the order of the base model's own
  // misfit, which no interval from this run bounds (the twin's 120-s run at
  // a steady wheel: r = -0.990 and an interval of +-7 counts 36 counts from
  // the truth). Not pinned: the pins, or a run whose wheel changes speed,
  // pin it.
  // The same, read off the wheel's speed changes and the model's output
  // alone (speed_follows_input.h): a steady wheel cannot tell the offset
  // from a delay whichever of two delays that fit alike identify took (the
  // joint fit's correlation, taken at that delay, can miss it: the twin's
  // 12-s steady run at -0.75 where another delay gave -0.99).
  p.speed_delay_correlation = OffsetDelayCorrelationFromSpeed(d);
  p.steady_wheel = std::abs(p.speed_delay_correlation) > kSteadyWheel;
  if (std::abs(report.shift_delay_correlation) > kInseparable || p.steady_wheel) {
    p.lo = grid.front(), p.hi = grid.back(), p.lo_at_edge = p.hi_at_edge = true;
    p.inseparable = true;
  }
  // The wheel's speed a filter of the input (speed_follows_input.h): not
  // pinned, whatever the delay's correlation says (a fed-forward wheel's
  // offset correlates with the delay at 0.1 and its least misses the truth
  // by five of the joint fit's sigmas).
  p.speed_input_share = SpeedShareFromInput(d);
  if (p.speed_input_share > kFollowsInput) {
    p.lo = grid.front(), p.hi = grid.back(), p.lo_at_edge = p.hi_at_edge = true;
    p.speed_follows_input = true;
  }

  report.position_shift_estimated = true;
  report.position_shift_counts = p.best;
  // Half-width, the larger side; unbounded where the interval reaches the
  // searched range (the run does not pin the offset).
  report.position_shift_ci95_counts = p.lo_at_edge || p.hi_at_edge ? kInf : std::max(p.hi - p.best, p.best - p.lo);
  if (p.halves_disagree) {
    char note[400];
    std::snprintf(note, sizeof note,
                  "the run's two halves put the offset at %+.1f and %+.1f counts from the rig file's, further apart "
                  "than the noise allows: what pins it is the model's misfit, not the data's noise; the interval is "
                  "widened to hold both halves' intervals",
                  p.first_half, p.second_half);
    report.confounded.push_back({"encoder_offset (first half)", "encoder_offset (second half)", NAN, note});
  }
  if (std::abs(report.shift_delay_correlation) > 0.9)
    report.confounded.push_back(
        {"encoder_offset.shift_counts", "delay.shift_s", report.shift_delay_correlation,
         "at a steady wheel speed a position error is a time error: the run pins the offset only through the "
         "changes of the wheel's speed, and its interval is as wide as they allow (pin scans pin it alone)"});
}

}  // namespace bead::explain
