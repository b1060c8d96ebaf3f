// The explain loop on measured-style series (uneven sampling, a stop in
// the middle): a first-order process y = G u plus one effect the model
// lacks, and white noise. Each effect must be found (and nothing else),
// its parameter recovered within its 95 % interval, the error lowered; on
// clean data nothing is added. The noise level (1 % of the output range)
// is what the intervals are judged against: a parameter must lie within
// 1.5 times its 95 % half-width (about 3 standard deviations), so that a
// correct estimate fails here with probability 0.3 %, not 5 %.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "libbead/explain/explain_loop.h"
#include "libbead/explain/model_series.h"
#include "libbead/model/identify.h"
#include "libbead/series/process_on.h"
#include "libbead/series/interpolate.h"

namespace bead::explain {
namespace {

constexpr double kPi = std::numbers::pi;

struct Data {
  std::vector<double> t, u;
};

// 60 s sampled at about 20 Hz with jitter, off between 28 and 33 s; the
// input a random staircase (steps every 0.5-2.5 s between 1 and 5).
Data MakeInput(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(0.035, 0.065), level(1.0, 5.0), hold(0.5, 2.5);
  Data d;
  double next_step = 0.0, value = 3.0;
  for (double t = 0.0; t < 60.0; t += jitter(rng)) {
    if (t > 28.0 && t < 33.0) continue;
    if (t >= next_step) value = level(rng), next_step = t + hold(rng);
    d.t.push_back(t);
    d.u.push_back(value);
  }
  return d;
}

model::TransferFunction Process() { return {{2.0}, {0.8, 1.0}, 0.2}; }  // 2 / (0.8 s + 1), 0.2 s delay

struct Case {
  std::vector<double> y;
  SeriesData data;
};

// The stretches: split at the stop (no samples for 5 s).
std::vector<Segment> Stretches(const Data& in) {
  return FindProcessOn(in.t, in.u, std::vector<double>(in.t.size(), 1.0)).segments;
}

// y = `effect` of the model's own (noiseless) series, plus noise; the
// process in steady state at the start of each stretch.
template <typename F>
Case Make(unsigned seed, F effect) {
  const Data in = MakeInput(seed);
  const auto segments = Stretches(in);
  const std::vector<double> steady = model::Predict(Process(), 0.0, in.t, in.u, {}, segments);
  const SeriesData clean = ModelSeries(in.t, in.u, steady, Process(), 0.0, segments);
  std::vector<double> y = effect(clean);
  std::mt19937_64 rng(seed + 100);
  std::normal_distribution<double> noise(0.0, 0.08);  // 1 % of the 2..10 output range
  for (double& v : y) v += noise(rng);
  Case c{y, ModelSeries(in.t, in.u, y, Process(), 0.0, segments, "units")};
  return c;
}

// An effect given sample by sample: f(clean series, i).
template <typename F>
auto EachSample(F f) {
  return [f](const SeriesData& d) {
    std::vector<double> y(d.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = f(d, i);
    return y;
  };
}

// Mean and standard deviation of the model's output: its operating level.
void Level(const SeriesData& d, double& mean, double& sd) {
  mean = sd = 0.0;
  for (double b : d.base) mean += b;
  mean /= d.base.size();
  for (double b : d.base) sd += (b - mean) * (b - mean);
  sd = std::sqrt(sd / (d.base.size() - 1));
}

// What was tried, for a failure's message.
std::string Tried(const ExplainReport& r) {
  std::string s = "tried (round name bic_drop F guarded_F):";
  for (const auto& c : r.candidates)
    s += " (" + std::to_string(c.round) + " " + c.name + " " + std::to_string(c.bic_drop) + " " +
         std::to_string(c.heldout_f) + " " + std::to_string(c.guarded_f) + ")";
  return s + (r.base.misspecified ? " [base misspecified]" : "");
}

const FittedParameter& Fitted(const AddedEffect& e, const std::string& name) {
  for (const auto& p : e.parameters)
    if (p.name == name) return p;
  throw std::runtime_error("no parameter " + name);
}

TEST(ExplainSeries, CleanDataGetsNothing) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Case c = Make(seed, [](const SeriesData& d) { return d.base; });
    const ExplainReport r = Explain(c.data);
    EXPECT_TRUE(r.effects_added.empty()) << "seed " << seed << ": " << r.effects_added.front().name;
    EXPECT_TRUE(r.after.whiteness.white) << "seed " << seed;
  }
}

TEST(ExplainSeries, FindsDrift) {
  const double slope = 0.4;  // units from the middle to the end of the record
  const Case c = Make(
      4, EachSample([&](const SeriesData& d, std::size_t i) { return d.base[i] + slope * (d.t[i] - 30.0) / 30.0; }));
  const ExplainReport r = Explain(c.data);
  ASSERT_EQ(r.effects_added.size(), 1u) << Tried(r);
  EXPECT_EQ(r.effects_added[0].name, "drift");
  const auto& p = Fitted(r.effects_added[0], "linear_units");
  EXPECT_NEAR(p.value, slope * 30.0 / 29.9, 1.5 * p.ci95);  // the record spans about 0..59.95 s
  EXPECT_LT(r.effects_added[0].rms_after, r.effects_added[0].rms_before);
}

TEST(ExplainSeries, FindsSaturatingBuildUp) {
  const double amplitude = 0.6, tau = 4.0;
  const Case c = Make(5, EachSample([&](const SeriesData& d, std::size_t i) {
                        return d.base[i] + amplitude * (1.0 - std::exp(-d.segment_time_s[i] / tau));
                      }));
  const ExplainReport r = Explain(c.data);
  ASSERT_GE(r.effects_added.size(), 1u) << Tried(r);
  EXPECT_EQ(r.effects_added[0].name, "buildup");
  const auto& a = Fitted(r.effects_added[0], "amplitude_units");
  const auto& t = Fitted(r.effects_added[0], "tau_s");
  EXPECT_NEAR(a.value, amplitude, 1.5 * a.ci95);
  EXPECT_NEAR(t.value, tau, 1.5 * t.ci95);
}

TEST(ExplainSeries, FindsLevelDependentGain) {
  const double g = 0.05;
  const Case c = Make(6, [&](const SeriesData& d) {
    double m, s;
    Level(d, m, s);
    std::vector<double> y(d.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = d.base[i] * (1.0 + g * (d.base[i] - m) / s);
    return y;
  });
  const ExplainReport r = Explain(c.data);
  ASSERT_GE(r.effects_added.size(), 1u) << Tried(r);
  EXPECT_EQ(r.effects_added[0].name, "level_gain");
  const auto& p = Fitted(r.effects_added[0], "rel_per_sd_level");
  EXPECT_NEAR(p.value, g, 1.5 * p.ci95);
}

TEST(ExplainSeries, FindsChangingDelay) {
  const double change = 0.3;  // s, start to end
  const Case c = Make(7, [&](const SeriesData& d) {
    std::vector<double> extra(d.size());
    for (std::size_t k = 0; k < extra.size(); ++k)
      extra[k] = change * (d.t[k] - 0.5 * (d.t.front() + d.t.back())) / (d.t.back() - d.t.front());
    return d.base_delayed(extra);
  });
  const ExplainReport r = Explain(c.data);
  ASSERT_GE(r.effects_added.size(), 1u) << Tried(r);
  EXPECT_EQ(r.effects_added[0].name, "delay_drift");
  const auto& p = Fitted(r.effects_added[0], "delay_change_s");
  EXPECT_NEAR(p.value, change, 1.5 * p.ci95);
}

// A process whose time constant grows with its level, 0.8 s at the mean
// output and 0.8 + 0.25 s per standard deviation above it (integrated
// finely); the model knows only 0.8 s. The catalogue's stand-in is a lag
// that grows with level. Since the base model's delay is refitted with
// every candidate, only the part of the lag that changes with level is
// left, and on this 60 s record its held-out F (5.9; 7.0 at 0.4 s per SD)
// stays under the Bonferroni level (9.5): it may go unfound. What must
// hold: it is never taken for another effect, and if added it is the
// level lag, positive, lowering the error.
constexpr double kLagPerSd = 0.25;
TEST(ExplainSeries, ATimeConstantThatChangesWithLevelIsNeverTakenForAnotherEffect) {
  const Case c = Make(9, [&](const SeriesData& d) {
    double m, s;
    Level(d, m, s);
    std::vector<double> y(d.size(), 0.0);
    double state = 0.0;
    for (std::size_t k = 1; k < d.size(); ++k) {
      const double dt = d.t[k] - d.t[k - 1];
      if (d.segment_time_s[k] == 0.0) state = 2.0 * d.u[k];            // each stretch starts in steady state
      const double u = InterpolateLinear(d.t, d.u, d.t[k - 1] - 0.2);  // the input, 0.2 s late
      const double tau = std::max(0.2, 0.8 + kLagPerSd * (state - m) / s);
      for (int sub = 0; sub < 20; ++sub) state += dt / 20 * (2.0 * u - state) / tau;
      y[k] = state;
    }
    return y;
  });
  const ExplainReport r = Explain(c.data);
  for (const auto& e : r.effects_added) EXPECT_EQ(e.name, "level_lag") << Tried(r);
  if (r.effects_added.empty()) return;
  const auto& p = Fitted(r.effects_added[0], "lag_s_per_sd_level");
  EXPECT_GT(p.value, 0.0);
  EXPECT_GT(p.value, p.ci95);  // significantly positive
  EXPECT_LT(r.effects_added[0].rms_after, 0.8 * r.effects_added[0].rms_before);
}

TEST(ExplainSeries, PeriodicStructureWithNoPartIsReportedUnexplained) {
  const Case c = Make(8, EachSample([&](const SeriesData& d, std::size_t i) {
                        return d.base[i] + 0.3 * std::sin(2 * kPi * 1.7 * d.t[i]);
                      }));
  const ExplainReport r = Explain(c.data);
  bool found = false;
  for (const auto& u : r.unexplained) found |= u.what == "periodic" && std::abs(u.frequency_hz - 1.7) < 0.05;
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace bead::explain
