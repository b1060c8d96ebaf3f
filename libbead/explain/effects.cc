#include "libbead/explain/effects.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "libbead/series/interpolate.h"

namespace bead::explain {
namespace {

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

double Sd(const std::vector<double>& v) {
  const double m = Mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return v.size() < 2 ? 0.0 : std::sqrt(s / static_cast<double>(v.size() - 1));
}

std::vector<double> Linspace(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(a + (b - a) * i / (n - 1));
  return v;
}

std::vector<double> Logspace(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(a * std::pow(b / a, static_cast<double>(i) / (n - 1)));
  return v;
}

Effect Make(std::string name, std::string description, Effect::Kind kind, std::string feature) {
  Effect e;
  e.name = std::move(name);
  e.description = std::move(description);
  e.kind = kind;
  e.feature = std::move(feature);
  return e;
}

// A channel's deviation from its mean through a first-order lag tau (exact
// for an input held between its samples) and a delay, at the times t.
std::vector<double> LaggedChannel(const Channel& ch, double tau, double delay, const std::vector<double>& t) {
  const std::size_t m = ch.t.size();
  std::vector<double> lagged(m);
  const double mean = Mean(ch.values);
  double state = ch.values.front() - mean;  // at rest at the first reading
  double last_dt = -1.0, a = 1.0;           // a log's steps repeat: exp only when one changes
  for (std::size_t k = 0; k < m; ++k) {
    const double dt = k ? ch.t[k] - ch.t[k - 1] : 0.0;
    if (dt != last_dt) a = std::exp(-dt / std::max(tau, 1e-6)), last_dt = dt;
    state = a * state + (1 - a) * (ch.values[k] - mean);
    lagged[k] = state;
  }
  std::vector<double> out(t.size());
  std::size_t hint = 0;  // the times run nearly in order
  for (std::size_t i = 0; i < t.size(); ++i) out[i] = InterpolateLinearNear(ch.t, lagged, t[i] - delay, hint);
  return out;
}

}  // namespace

std::vector<std::vector<double>> Effect::Columns(const SeriesData& d, const double* nl) const {
  const std::size_t n = d.size();
  std::vector<std::vector<double>> cols;
  if (kind == Kind::kPositionShift || IsDelay()) return cols;
  if (part >= 0) {
    const auto& a = d.parts[static_cast<std::size_t>(part)].angle_rad;
    std::vector<double> c(n), s(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = std::cos(harmonic * a[i]), s[i] = std::sin(harmonic * a[i]);
    cols.push_back(std::move(c));
    cols.push_back(std::move(s));
    return cols;
  }
  if (feature == "dynamics") return d.dynamics;
  if (feature == "channel") return {LaggedChannel(d.channels[static_cast<std::size_t>(channel)], nl[0], nl[1], d.t)};
  if (feature == "initial") return d.initial;
  if (feature == "input_part") return {d.input_parts[static_cast<std::size_t>(channel)].values};
  std::vector<double> c(n, 0.0);
  if (feature == "scale" || feature == "bias") {
    std::fill(c.begin(), c.end(), 1.0);
  } else if (feature == "drift") {
    const double t0 = 0.5 * (d.t.front() + d.t.back()), half = 0.5 * (d.t.back() - d.t.front());
    std::vector<double> c2(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = (d.t[i] - t0) / half;
      c[i] = x;
      c2[i] = x * x;
    }
    cols.push_back(std::move(c));
    cols.push_back(std::move(c2));
    return cols;
  } else if (feature == "time_to_laser") {
    // Cooling shrink approached with time constant tau after laying: the
    // area left at time-to-laser dt is 1 - s (1 - exp(-dt / tau)). Scaled
    // so that the parameter is the shrink at the mean time-to-laser m,
    // which the data pins down even when tau (the curvature) it barely does.
    const double m = Mean(d.time_to_laser_s), tau = std::max(nl[0], 1e-3);
    const double at_mean = 1.0 - std::exp(-m / tau);
    for (std::size_t i = 0; i < n; ++i) c[i] = -(1.0 - std::exp(-d.time_to_laser_s[i] / tau)) / at_mean;
  } else if (feature == "height") {
    const double m = Mean(d.height_mm);
    for (std::size_t i = 0; i < n; ++i) c[i] = (d.height_mm[i] - m) / m;
  } else if (feature == "buildup") {
    for (std::size_t i = 0; i < n; ++i) c[i] = 1.0 - std::exp(-d.segment_time_s[i] / nl[0]);
  } else if (feature == "level") {
    const double m = Mean(d.base), s = Sd(d.base);
    for (std::size_t i = 0; i < n; ++i) c[i] = s > 0 ? (d.base[i] - m) / s : 0.0;
  }
  cols.push_back(std::move(c));
  return cols;
}

double Effect::PositionShift(const double* nl) const { return kind == Kind::kPositionShift ? nl[0] : 0.0; }

void Effect::AddDelay(const SeriesData& d, const double* nl, std::vector<double>& delay) const {
  if (kind == Kind::kDelay) {
    for (double& x : delay) x += nl[0];
  } else if (kind == Kind::kDelayDrift) {
    // The delay grows linearly over the record: nl[0] seconds from start to end.
    const double t0 = 0.5 * (d.t.front() + d.t.back()), span = d.t.back() - d.t.front();
    for (std::size_t i = 0; i < delay.size(); ++i) delay[i] += nl[0] * (d.t[i] - t0) / span;
  } else if (kind == Kind::kDelayLevel) {
    // A lag that grows with the operating level (standardised model
    // output): on signals slower than it, a first-order time constant acts
    // as such a lag, so this stands for a time constant that changes with level.
    const double m = Mean(d.base), s = Sd(d.base);
    for (std::size_t i = 0; i < delay.size(); ++i) delay[i] += s > 0 ? nl[0] * (d.base[i] - m) / s : 0.0;
  }
}

namespace {

// Once and twice per revolution of each rotating part that turns a few
// times in the record.
void AddPeriodicTerms(const SeriesData& d, std::vector<Effect>& out) {
  using K = Effect::Kind;
  for (std::size_t p = 0; p < d.parts.size(); ++p) {
    const auto& a = d.parts[p].angle_rad;
    const double turns = std::abs(a.back() - a.front()) / (2 * std::numbers::pi);
    if (turns < 2.0) continue;  // a periodic term needs the part to turn a few times
    for (int h = 1; h <= 2; ++h) {
      Effect e = Make((h == 1 ? "once_per_rev[" : "twice_per_rev[") + d.parts[p].name + "]",
                      (h == 1 ? "once" : "twice") + std::string(" per revolution of the ") + d.parts[p].name +
                          " (runout, eccentricity)",
                      K::kMultiplicative, "periodic");
      e.part = static_cast<int>(p);
      e.harmonic = h;
      e.tracks = d.parts[p].name;
      e.linear = {"cos_rel", "sin_rel"};
      out.push_back(e);
    }
  }
}

// Each recorded channel that varies: the output following it through its
// own lag and delay.
void AddChannelTerms(const SeriesData& d, std::vector<Effect>& out) {
  using K = Effect::Kind;
  const double span = d.t.back() - d.t.front();
  for (std::size_t k = 0; k < d.channels.size(); ++k) {
    const Channel& ch = d.channels[k];
    if (ch.t.size() < 2 || !(Sd(ch.values) > 0)) continue;  // a constant channel explains nothing
    const std::string unit = ch.unit.empty() ? "unit" : ch.unit;
    Effect e = Make("channel[" + ch.name + "]",
                    "the output follows the recorded channel " + ch.name + " through its own lag and delay",
                    K::kMultiplicative, "channel");
    e.channel = static_cast<int>(k);
    e.tracks = ch.name;
    e.nonlinear = {"lag_s", "delay_s"};
    e.grid = {Logspace(0.05, std::max(1.0, span / 4), 21), Linspace(0.0, std::min(2.0, span / 10), 11)};
    e.linear = {"rel_per_" + unit};
    out.push_back(e);
  }
}

}  // namespace

std::vector<Effect> Catalogue(const SeriesData& d, const CatalogueOptions& o) {
  using K = Effect::Kind;
  std::vector<Effect> out;
  const double span = d.t.back() - d.t.front();
  if (o.has_wheel && d.shifted) {
    Effect e = Make("encoder_offset", "the nozzle-to-laser offset is wrong: data misaligned in wheel position",
                    K::kPositionShift, "offset");
    e.nonlinear = {"shift_counts"};
    e.grid = {Linspace(-o.position_range_counts, o.position_range_counts, 61)};
    out.push_back(e);
  }
  if (d.shifted || d.base_delayed) {
    Effect f = Make("delay_drift", "the delay changes over the record", K::kDelayDrift, "delay_drift");
    f.nonlinear = {"delay_change_s"};
    f.grid = {Linspace(-o.delay_range_s, o.delay_range_s, 41)};
    out.push_back(f);
    Effect g = Make("level_lag", "the response lags more at a higher level (a time constant changing with level)",
                    K::kDelayLevel, "level_lag");
    g.nonlinear = {"lag_s_per_sd_level"};
    g.grid = {Linspace(-0.5 * o.delay_range_s, 0.5 * o.delay_range_s, 41)};
    out.push_back(g);
  }
  AddPeriodicTerms(d, out);
  if (!d.time_to_laser_s.empty() && Sd(d.time_to_laser_s) > 0.05 * Mean(d.time_to_laser_s)) {
    Effect e = Make("cooling_shrink", "the bead shrinks between laying and measuring (varies with time to laser)",
                    K::kMultiplicative, "time_to_laser");
    e.nonlinear = {"tau_s"};
    const double m = Mean(d.time_to_laser_s);
    e.grid = {Logspace(0.1 * m, 10.0 * m, 25)};
    e.linear = {"shrink_at_mean_frac"};
    out.push_back(e);
  }
  if (!d.height_mm.empty() && Sd(d.height_mm) > 0.02 * Mean(d.height_mm)) {
    Effect e = Make("height_dependence", "the error grows with bead height (occlusion left over)", K::kMultiplicative,
                    "height");
    e.linear = {"rel_per_rel_height"};
    out.push_back(e);
  }
  Effect drift = Make("drift", "slow drift over the record (linear and quadratic)", K::kAdditive, "drift");
  drift.linear = {"linear_" + d.y_unit, "quadratic_" + d.y_unit};
  out.push_back(drift);
  if (!d.segment_time_s.empty()) {
    Effect e = Make("buildup", "a saturating build-up after each start (heat accumulating)", K::kAdditive, "buildup");
    e.nonlinear = {"tau_s"};
    e.grid = {Logspace(span / 200.0, span, 25)};
    e.linear = {"amplitude_" + d.y_unit};
    out.push_back(e);
  }
  AddChannelTerms(d, out);
  Effect level = Make("level_gain", "the gain changes with the operating level", K::kMultiplicative, "level");
  level.linear = {"rel_per_sd_level"};
  out.push_back(level);
  return out;
}

std::vector<Effect> BaseRefit(const SeriesData& d, const CatalogueOptions& o) {
  using K = Effect::Kind;
  std::vector<Effect> out;
  Effect s = Make("gain", "the base model's gain, refitted (a factor on its prediction)", K::kMultiplicative, "scale");
  s.linear = {"rel"};
  out.push_back(s);
  Effect b = Make("operating_point", "the base model's operating point, refitted (a constant)", K::kAdditive, "bias");
  b.linear = {"value_" + d.y_unit};
  out.push_back(b);
  if (!d.initial.empty()) {
    Effect e = Make("initial_state", "the base model's initial state in each stretch, refitted (its free response)",
                    K::kAdditive, "initial");
    for (std::size_t k = 0; k < d.initial.size(); ++k) e.linear.push_back("free_" + std::to_string(k));
    out.push_back(e);
  }
  for (std::size_t k = 0; k < d.input_parts.size(); ++k) {
    Effect e = Make("gain[" + d.input_parts[k].name + "]",
                    "the base model's part from " + d.input_parts[k].name + ": its gain, refitted (a factor on it)",
                    K::kAdditive, "input_part");
    e.channel = static_cast<int>(k);
    e.linear = {"rel"};
    out.push_back(e);
  }
  if (d.shifted || d.base_delayed) {
    Effect e =
        Make("delay", "the base model's delay, refitted (measurement and model shifted in time)", K::kDelay, "delay");
    e.nonlinear = {"shift_s"};
    e.grid = {Linspace(-o.delay_range_s, o.delay_range_s, 41)};
    out.push_back(e);
  }
  return out;
}

Effect DynamicsCorrection(const SeriesData& d) {
  Effect e = Make(d.dynamics.empty() ? "" : "dynamics_correction",
                  "a linear correction of the base model's dynamics (filters of its input)", Effect::Kind::kAdditive,
                  "dynamics");
  // (Appended, not `"c" + string`: GCC 12's -Wrestrict false alarm.)
  for (std::size_t k = 0; k < d.dynamics.size(); ++k) e.linear.push_back(std::string("c").append(std::to_string(k)));
  return e;
}

}  // namespace bead::explain
