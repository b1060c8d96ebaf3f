// Identification with two inputs (model/identify_multi.h): a screw speed
// acting through a first-order lag and a delay, and a barrel temperature
// cycling under bang-bang control acting through the melt's slower lag
// (seed 003, section 3.4: the flow depends on screw speed and temperature),
// with white measurement noise. The two transfer functions come back, each
// gain within what the noise allows, and inputs that move together are
// said to trade.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

#include "libbead/model/identify_multi.h"
#include "libbead/model/predict.h"
#include "tests/support/random_steps.h"
#include "tests/support/run_cli.h"

namespace bead::model {
namespace {

constexpr double kDt = 0.05, kNoise = 1.0;
const TransferFunction kScrew{{9.0}, {0.4, 1.0}, 0.2};  // mm^3/s per rpm, lag 0.4 s, delay 0.2 s
const TransferFunction kMelt{{2.7}, {3.0, 1.0}, 0.5};   // mm^3/s per C, the melt's lag 3 s

struct TwoInputRun {
  std::vector<double> t, rpm, temp, flow;
};

// A heater switched 4 C either side of its setpoint, heating and cooling
// at 1 C/s (a triangle of period 16 s), the operator moving the setpoint
// between 190 and 210 C every 40 s. A triangle alone shows the melt's
// response at its harmonics only, where gain, lag and delay trade; the
// setpoint's steps pin the gain.
std::vector<double> BangBang(std::mt19937_64& rng, const std::vector<double>& t) {
  std::uniform_real_distribution<double> setpoint(190.0, 210.0);
  std::vector<double> out;
  double v = 200.0, sp = 200.0;
  bool heating = true;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (i % 800 == 0) sp = setpoint(rng);
    out.push_back(v);
    v += (heating ? 1.0 : -1.0) * kDt;
    if (v >= sp + 4) heating = false;
    if (v <= sp - 4) heating = true;
  }
  return out;
}

TwoInputRun MakeRun(unsigned seed, int samples) {
  std::mt19937_64 rng(seed);
  const auto steps = test::RandomSteps(rng, 20.0, 40.0, samples, 60, kDt);
  TwoInputRun r{steps.t, steps.u, BangBang(rng, steps.t), {}};
  const auto a = Predict(kScrew, 0.0, r.t, r.rpm, {}), b = Predict(kMelt, -540.0, r.t, r.temp, {});
  std::normal_distribution<double> noise(0.0, kNoise);
  for (std::size_t i = 0; i < r.t.size(); ++i) r.flow.push_back(a[i] + b[i] + noise(rng));
  return r;
}

// The standard error of a gain on a part whose shape is known: the noise
// over the root sum of squares of the unit-gain part about its mean.
double GainSe(const TransferFunction& tf, const std::vector<double>& t, const std::vector<double>& u) {
  const TransferFunction unit{{tf.num[0] / tf.DcGain()}, tf.den, tf.delay_s};
  const auto x = Predict(unit, 0.0, t, u, {});
  double m = 0, ss = 0;
  for (double v : x) m += v / static_cast<double>(x.size());
  for (double v : x) ss += (v - m) * (v - m);
  return kNoise / std::sqrt(ss);
}

TEST(IdentifyMultiInput, RecoversEachInputsTransferFunction) {
  const TwoInputRun r = MakeRun(7, 3000);
  IdentifyOptions o;
  o.poles = 1;
  o.zeros = 0;
  o.max_delay_s = 1.0;
  const MultiInputModel m = IdentifyMultiInput(r.t, {r.rpm, r.temp}, r.flow, {o, o});
  ASSERT_TRUE(m.ok) << m.reason;
  EXPECT_TRUE(m.converged) << m.sweeps;
  ASSERT_EQ(m.inputs.size(), 2u);
  // Gains within 5 standard errors of a gain on a known shape (the
  // inputs' long holds pin the gain nearly apart from the lag), the lags
  // to 10 % and the delay to a sample.
  EXPECT_NEAR(m.inputs[0].tf.DcGain(), 9.0, 5 * GainSe(kScrew, r.t, r.rpm));
  EXPECT_NEAR(m.inputs[1].tf.DcGain(), 2.7, 5 * GainSe(kMelt, r.t, r.temp));
  EXPECT_NEAR(m.inputs[0].process.Tp_s[0], 0.4, 0.04);
  EXPECT_NEAR(m.inputs[1].process.Tp_s[0], 3.0, 0.3);
  EXPECT_NEAR(m.inputs[0].tf.delay_s, 0.2, kDt);
  // What is left is the noise: fit % against 100 (1 - sigma / sd(y)).
  double my = 0, vy = 0;
  for (double v : r.flow) my += v / static_cast<double>(r.flow.size());
  for (double v : r.flow) vy += (v - my) * (v - my) / static_cast<double>(r.flow.size());
  const double ideal = 100 * (1 - kNoise / std::sqrt(vy));
  EXPECT_NEAR(m.fit_percent, ideal, 0.3);
  EXPECT_LT(m.max_input_correlation, 0.9);
  EXPECT_TRUE(m.note.empty()) << m.note;
  // The screw speed alone leaves the temperature's part: worse by BIC.
  const IdentifiedModel one = IdentifyTransferFunction(r.t, r.rpm, r.flow, o);
  ASSERT_TRUE(one.ok);
  EXPECT_LT(m.criteria.bic, one.criteria.bic - 100);
  EXPECT_LT(one.fit_percent, m.fit_percent - 2);
  // On another run the model predicts as well as on its own.
  const TwoInputRun v = MakeRun(8, 3000);
  std::vector<TransferFunction> tfs = {m.inputs[0].tf, m.inputs[1].tf};
  EXPECT_NEAR(FitPercent(v.flow, PredictMultiInput(tfs, m.offset, v.t, {v.rpm, v.temp}, v.flow)), ideal, 1.0);
}

TEST(IdentifyMultiInput, InputsThatMoveTogetherAreSaidToTrade) {
  TwoInputRun r = MakeRun(9, 2000);
  // A second input that is the first, rescaled, with a little noise: its
  // part and the first's cannot be told apart.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> jitter(0.0, 0.05);
  std::vector<double> twin;
  for (double v : r.rpm) twin.push_back(0.5 * v + jitter(rng));
  IdentifyOptions o;
  o.poles = 1;
  o.zeros = 0;
  const MultiInputModel m = IdentifyMultiInput(r.t, {r.rpm, twin}, r.flow, {o, o});
  ASSERT_TRUE(m.ok) << m.reason;
  EXPECT_GT(m.max_input_correlation, 0.9);
  EXPECT_NE(m.note.find("cannot tell"), std::string::npos) << m.note;
}

TEST(IdentifyMultiInput, CommandWritesAModelOfSeveralInputsThatExplainTakes) {
  test::TempDir dir;
  const TwoInputRun r = MakeRun(11, 1600);
  std::string csv = "t_s,screw_rpm,barrel_temp_c,flow_mm3_s\n";
  for (std::size_t i = 0; i < r.t.size(); ++i)
    csv += std::to_string(r.t[i]) + "," + std::to_string(r.rpm[i]) + "," + std::to_string(r.temp[i]) + "," +
           std::to_string(r.flow[i]) + "\n";
  test::WriteText(dir / "run.csv", csv);
  auto [status, out] = test::RunCli(dir, "identify " + (dir / "run.csv") +
                                             " --time t_s --input screw_rpm,barrel_temp_c --output flow_mm3_s "
                                             "--poles 1 --zeros 0 -o " +
                                             (dir / "m.json"));
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("input 2, barrel_temp_c"), std::string::npos) << out;
  const auto j = nlohmann::json::parse(test::ReadText(dir / "m.json"));
  EXPECT_EQ(j["format"], "bead model 3");
  ASSERT_EQ(j["inputs"].size(), 2u);
  EXPECT_EQ(j["inputs"][1]["input"], "barrel_temp_c");
  const double k2 = j["inputs"][1]["num"].back().get<double>() / j["inputs"][1]["den"].back().get<double>();
  EXPECT_NEAR(k2, 2.7, 0.1 * 2.7);
  // A per-input list of the wrong length is refused, naming the option.
  std::tie(status, out) =
      test::RunCli(dir, "identify " + (dir / "run.csv") +
                            " --time t_s --input screw_rpm,barrel_temp_c --output flow_mm3_s --poles 1,2,3");
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("--poles gives 3 values"), std::string::npos) << out;
  // The two-input model as explain's base: nothing is missing from it, so
  // nothing is added; with the screw speed alone the temperature's part is
  // what explain finds, as a recorded channel.
  std::tie(status, out) = test::RunCli(dir, "explain " + (dir / "run.csv") +
                                                " --time t_s --input screw_rpm,barrel_temp_c --output "
                                                "flow_mm3_s --model " +
                                                (dir / "m.json") + " -o " + (dir / "e.json"));
  ASSERT_EQ(status, 0) << out;
  const auto e = nlohmann::json::parse(test::ReadText(dir / "e.json"));
  EXPECT_TRUE(e["effects_added"].empty()) << e["effects_added"].dump();
  EXPECT_EQ(e["model"]["more_inputs"][0]["input"], "barrel_temp_c");
  EXPECT_TRUE(e["base_refit"].contains("gain[barrel_temp_c]")) << e["base_refit"].dump();
  std::tie(status, out) = test::RunCli(dir, "explain " + (dir / "run.csv") +
                                                " --time t_s --input screw_rpm --output flow_mm3_s --poles 1 "
                                                "--zeros 0 --channels barrel_temp_c -o " +
                                                (dir / "e1.json"));
  ASSERT_EQ(status, 0) << out;
  const auto e1 = nlohmann::json::parse(test::ReadText(dir / "e1.json"));
  ASSERT_FALSE(e1["effects_added"].empty()) << out;
  EXPECT_EQ(e1["effects_added"][0]["name"], "channel[barrel_temp_c]") << out;
}

}  // namespace
}  // namespace bead::model
