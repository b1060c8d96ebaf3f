// PID designs on seed 004's models (Cojuhari et al., eq. 11-15, the
// extruder's heater): the maximum stability degree design equals its
// analytic optimum where there is one, its J is the closed loop's
// rightmost root as counted by the argument principle (independently of
// the design's root finder), no PID of the paper's Table I has a larger
// J, and every rule's loop is stable with positive margins.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "libbead/control/closed_loop.h"
#include "libbead/control/pid_tuning.h"

namespace bead::control {
namespace {

using model::TransferFunction;
using C = std::complex<double>;

// k e^(-tau s) / prod (T_i s + 1)
TransferFunction Lags(double k, std::vector<double> T, double tau) {
  std::vector<double> den = {1.0};
  for (double t : T) {
    std::vector<double> next(den.size() + 1, 0.0);
    for (std::size_t i = 0; i < den.size(); ++i) next[i] += t * den[i], next[i + 1] += den[i];
    den = next;
  }
  return {{k}, den, tau};
}

// Seed 004, eq. 11-15.
const TransferFunction kEq11 = Lags(1.0035, {44.2696}, 2.847);
const TransferFunction kEq12 = Lags(1.0041, {37.87, 38.55}, 0.002);
const TransferFunction kEq13 = Lags(1.0031, {44.003, 2.2272}, 0.0);
const TransferFunction kEq14 = Lags(1.0033, {44.1315, 2.0042, 1.9689}, 0.0);
const TransferFunction kEq15 = Lags(1.0035, {28.3325, 14.1663}, 2.847);

// Zeros of D inside the rectangle [re_lo, re_hi] x [-w, w], by the
// argument principle: the winding of D along the boundary, in steps fine
// enough that the phase moves less than a quarter turn between them.
int ZerosInside(const QuasiPolynomial& d, double re_lo, double re_hi, double w) {
  std::vector<C> corners = {{re_lo, -w}, {re_hi, -w}, {re_hi, w}, {re_lo, w}, {re_lo, -w}};
  double turn = 0;
  for (std::size_t e = 0; e + 1 < corners.size(); ++e) {
    const int n = 200000;
    C prev = d(corners[e]);
    for (int k = 1; k <= n; ++k) {
      const C s = corners[e] + (corners[e + 1] - corners[e]) * (static_cast<double>(k) / n);
      const C v = d(s);
      turn += std::arg(v / prev);
      prev = v;
    }
  }
  return static_cast<int>(std::lround(turn / (2 * M_PI)));
}

// J checked without the design's root finder: no zero right of -J (1 %
// in), one at least within 1 % left of it.
void ExpectRightmostAt(const TransferFunction& g, const Pid& pid, double J) {
  const QuasiPolynomial d = Characteristic(g, pid);
  const double re_hi = 2.0, w = g.delay_s > 0 ? 60.0 / g.delay_s : 50.0;
  EXPECT_EQ(ZerosInside(d, -0.99 * J, re_hi, w), 0) << "J " << J;
  EXPECT_GE(ZerosInside(d, -1.01 * J, re_hi, w), 1) << "J " << J;
}

// Model 14: the closed loop's characteristic polynomial
//   a0 s^4 + a1 s^3 + (a2 + k kd) s^2 + (1 + k kp) s + k ki,
// a0 = T1 T2 T3, a1 = T1 T2 + T1 T3 + T2 T3, a2 = T1 + T2 + T3, equals
// a0 (s + J)^4 for J = a1 / (4 a0) (its roots' mean is fixed: no PID puts
// them all further left), kd = (6 J^2 a0 - a2) / k, kp = (4 J^3 a0 - 1) / k,
// ki = J^4 a0 / k. Table I row 4 is this design (J 0.26, kp 10.836,
// ki 0.7611, kd 21.032) to its printed digits.
TEST(MaxStability, ThirdOrderLagsPutEveryRootAtMinusJ) {
  const double T1 = 44.1315, T2 = 2.0042, T3 = 1.9689, k = 1.0033;
  const double a0 = T1 * T2 * T3, a1 = T1 * T2 + T1 * T3 + T2 * T3, a2 = T1 + T2 + T3;
  const double J = a1 / (4 * a0);
  const Pid analytic{(4 * J * J * J * a0 - 1) / k, J * J * J * J * a0 / k, (6 * J * J * a0 - a2) / k, 0};
  const Design d = DesignPid(kEq14, "max-stability");
  ASSERT_TRUE(d.ok) << d.reason;
  // A fourfold root moves by (relative coefficient error)^(1/4): the
  // printed gains' 6 digits (half a unit: 5e-6) split it by up to
  // (5e-6)^(1/4) = 4.7 %.
  EXPECT_NEAR(d.pid.kp, analytic.kp, 1e-5 * analytic.kp);
  EXPECT_NEAR(d.pid.ki, analytic.ki, 1e-5 * analytic.ki);
  EXPECT_NEAR(d.pid.kd, analytic.kd, 1e-5 * analytic.kd);
  EXPECT_NEAR(d.stability_degree, J, 0.047 * J);
  EXPECT_NEAR(J, 0.26, 0.005);
  EXPECT_NEAR(analytic.kp, 10.836, 0.01 * 10.836);
  EXPECT_NEAR(analytic.ki, 0.7611, 0.01 * 0.7611);
  EXPECT_NEAR(analytic.kd, 21.032, 0.01 * 21.032);
  ExpectRightmostAt(kEq14, d.pid, d.stability_degree);
}

// Model 13 (second order, no delay): the loop is of third order and a PID
// places all three roots anywhere: J has no maximum. At J = 0.3 the
// triple root gives Table I row 3 (kp 25.382, ki 2.6379, kd 41.843).
TEST(MaxStability, SecondOrderLagsHaveNoMaximumAndRowThreeAtJ03) {
  const Design free = DesignPid(kEq13, "max-stability");
  EXPECT_FALSE(free.ok);
  EXPECT_TRUE(free.unbounded) << free.reason;
  const Design d = DesignPid(kEq13, "max-stability", 0.3);
  ASSERT_TRUE(d.ok);
  EXPECT_NEAR(d.pid.kp, 25.382, 1e-4 * 25.382);
  EXPECT_NEAR(d.pid.ki, 2.6379, 1e-4 * 2.6379);
  EXPECT_NEAR(d.pid.kd, 41.843, 1e-4 * 41.843);
  // A triple root split by 6-digit gains: up to (5e-6)^(1/3) = 1.7 %.
  EXPECT_NEAR(d.stability_degree, 0.3, 0.017 * 0.3);
  ExpectRightmostAt(kEq13, d.pid, d.stability_degree);
}

// The delay models: J from the design is the rightmost root the argument
// principle finds, and no PID of Table I does better than the maximum.
TEST(MaxStability, DelayModelsJIsTheRightmostRootAndAtLeastTableIs) {
  struct Row {
    const TransferFunction* g;
    Pid table;
  };
  const Row rows[] = {
      {&kEq11, {7.5251, 0.3859, 20.704, 0}}, {&kEq12, {2.673, 0.035, 50.407, 0}}, {&kEq15, {2.6854, 0.072, 23.524, 0}}};
  for (const Row& r : rows) {
    const Design d = DesignPid(*r.g, "max-stability");
    ASSERT_TRUE(d.ok) << d.reason;
    EXPECT_GT(d.stability_degree, 0);
    ExpectRightmostAt(*r.g, d.pid, d.stability_degree);
    const double table_j = -FindRightmostRoot(Characteristic(*r.g, r.table)).real_part;
    EXPECT_GE(d.stability_degree, 0.99 * table_j) << "table's J " << table_j;
  }
}

TEST(PidRules, EveryMethodsLoopIsStableWithMargins) {
  for (const TransferFunction* g : {&kEq11, &kEq12, &kEq13, &kEq14, &kEq15})
    for (const std::string& m : Methods()) {
      const Design d =
          DesignPid(*g, m, m == "max-stability" && g == &kEq13 ? std::optional<double>(0.3) : std::nullopt);
      ASSERT_TRUE(d.ok) << m << ": " << d.reason;
      EXPECT_GT(d.stability_degree, 0) << m;
      if (!(d.stability_degree > 0)) continue;
      // The margins: a crossover with positive phase margin, a finite
      // peak sensitivity. (The gain margin of a conditionally stable loop,
      // as the max-stability designs on the almost delay-free models are,
      // is below 1 by the classic definition and says nothing alone.)
      const Margins mg = ComputeMargins(*g, d.pid);
      EXPECT_GT(mg.phase_margin_deg, 0.0) << m;
      EXPECT_TRUE(std::isfinite(mg.ms)) << m;
      // Integral action: the setpoint is reached and held.
      const StepFigures s = SetpointStep(*g, d.pid, std::min(40.0 / d.stability_degree, 5000.0));
      EXPECT_NEAR(s.y.back(), 1.0, 0.05) << m;
    }
}

// SIMC on a first order plus delay (Skogestad 2003, tauc = theta):
// Kc = tau / (2 k theta), tauI = min(tau, 8 theta), a PI.
TEST(PidRules, SimcOnFirstOrderPlusDelayIsSkogestadsPi) {
  const Design d = DesignPid(kEq11, "simc");
  ASSERT_TRUE(d.ok);
  const double kc = 44.2696 / (2 * 1.0035 * 2.847), ti = std::min(44.2696, 8 * 2.847);
  EXPECT_NEAR(d.pid.kp, kc, 1e-5 * kc);
  EXPECT_NEAR(d.pid.ki, kc / ti, 1e-5 * kc / ti);
  EXPECT_EQ(d.pid.kd, 0.0);
}

}  // namespace
}  // namespace bead::control
