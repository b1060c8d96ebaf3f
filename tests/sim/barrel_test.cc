// The barrel's temperature as the twin records it: a bang-bang heater
// cycles with the period its heat balance gives, a PID holds the setpoint,
// and the flow follows the melt's temperature by the configured gain.
#include "libbead/sim/barrel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_config.h"

namespace bead::sim {
namespace {

std::vector<double> Readings(const BarrelConfig& c, double dt, double seconds) {
  Barrel b(c, dt);
  std::mt19937_64 rng(7);
  std::vector<double> out;
  for (int i = 0; i < static_cast<int>(seconds / dt); ++i) {
    b.Step(rng);
    out.push_back(b.reading_c());
  }
  return out;
}

// Bang-bang between setpoint -+ band/2 as the thermocouple reads it. A
// first-order sensor on a ramp of rate r lags it by r tau_s, so the wall
// turns at the thresholds -+ r tau_s; it then heats from T_lo to T_hi in
// tau_w ln((T_h - T_lo) / (T_h - T_hi)) and cools back in
// tau_w ln((T_hi - T_a) / (T_lo - T_a)).
TEST(Barrel, BangBangCyclesWithThePeriodItsHeatBalanceGives) {
  BarrelConfig c;
  c.noise_c = 0.0;
  const double dt = 0.001;
  const std::vector<double> r = Readings(c, dt, 200.0);
  std::vector<double> ups;  // upward crossings of the setpoint after the first cycle
  for (std::size_t i = 1; i < r.size(); ++i)
    if (i * dt > 40 && r[i - 1] < c.setpoint_c && r[i] >= c.setpoint_c) ups.push_back(i * dt);
  ASSERT_GE(ups.size(), 4u);
  const double period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
  const double rate = (c.heater_c - c.setpoint_c) / c.wall_tau_s;  // about 1 C/s near the setpoint
  const double lo = c.setpoint_c - 0.5 * c.band_c - rate * c.sensor_tau_s;
  const double hi = c.setpoint_c + 0.5 * c.band_c + rate * c.sensor_tau_s;
  const double expected = c.wall_tau_s * (std::log((c.heater_c - lo) / (c.heater_c - hi)) +
                                          std::log((hi - c.ambient_c) / (lo - c.ambient_c)));
  EXPECT_NEAR(period, expected, 0.1 * expected) << "ramp-lag estimate " << expected << " s";
  double min = 1e9, max = -1e9;
  for (std::size_t i = static_cast<std::size_t>(40 / dt); i < r.size(); ++i)
    min = std::min(min, r[i]), max = std::max(max, r[i]);
  // The reading turns just past the band (the wall's lag behind the duty).
  EXPECT_LT(min, c.setpoint_c - 0.5 * c.band_c);
  EXPECT_GT(min, c.setpoint_c - 0.5 * c.band_c - 1.0);
  EXPECT_GT(max, c.setpoint_c + 0.5 * c.band_c);
  EXPECT_LT(max, c.setpoint_c + 0.5 * c.band_c + 1.0);
}

TEST(Barrel, PidHoldsTheSetpoint) {
  BarrelConfig c;
  c.control = BarrelConfig::Control::kPid;
  c.noise_c = 0.0;
  const std::vector<double> r = Readings(c, 0.001, 120.0);
  for (std::size_t i = 60000; i < r.size(); ++i) ASSERT_NEAR(r[i], c.setpoint_c, 0.05) << "at " << i * 0.001 << " s";
}

// The same seed with and without the temperature's effect: the flow's
// ratio is 1 + k (T_melt - setpoint), T_melt lagging the wall, so (ratio -
// 1) / k stays within the range the reading covers (widened by the lags'
// overshoot) and swings with it.
TEST(Barrel, FlowFollowsTheMeltTemperatureByTheConfiguredGain) {
  SimConfig c;
  c.duration_s = 40.0;
  c.sensor.points = 32;
  c.warm_start = true;
  c.barrel.record = true;
  const SimulatedRun plain = Simulate(c);
  c.barrel.flow_per_c = 0.01;
  const SimulatedRun hot = Simulate(c);
  ASSERT_EQ(plain.run.log->channels.size(), 1u);
  const LogChannel& temp = plain.run.log->channels[0];
  EXPECT_EQ(temp.name, "barrel_temp_c");
  EXPECT_EQ(temp.unit, "C");
  const auto& q0 = plain.truth.flow.flow_mm3_s;
  const auto& q1 = hot.truth.flow.flow_mm3_s;
  ASSERT_EQ(q0.size(), q1.size());
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 0; i < q0.size(); ++i) {
    if (!(q0[i] > 1.0)) continue;
    const double excess = (q1[i] / q0[i] - 1.0) / 0.01;
    lo = std::min(lo, excess), hi = std::max(hi, excess);
  }
  double t_lo = 1e9, t_hi = -1e9;
  for (double v : temp.values) t_lo = std::min(t_lo, v - 200.0), t_hi = std::max(t_hi, v - 200.0);
  EXPECT_GT(lo, t_lo - 2.0);
  EXPECT_LT(hi, t_hi + 2.0);
  EXPECT_GT(hi - lo, 0.5 * (t_hi - t_lo)) << "the flow must swing with the melt";
}

TEST(Barrel, ConfigReadsAndRefusesAHeaterThatCannotReachTheSetpoint) {
  const SimConfig c = ParseSimConfig("barrel: {record: true, control: pid, flow_per_c: 0.02}\n", "t.yaml");
  EXPECT_TRUE(c.barrel.record);
  EXPECT_EQ(c.barrel.control, BarrelConfig::Control::kPid);
  EXPECT_DOUBLE_EQ(c.barrel.flow_per_c, 0.02);
  EXPECT_THROW(ParseSimConfig("barrel: {heater_c: 150}\n", "t.yaml"), std::exception);
  EXPECT_THROW(ParseSimConfig("barrel: {control: fuzzy}\n", "t.yaml"), std::exception);
}

}  // namespace
}  // namespace bead::sim
