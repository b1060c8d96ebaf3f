// The lateral registration of a new layer on the one below
// (part/registration.h): tracked from the pass's last shift where it can
// be, scanned where it cannot, the same shift either way.
#include "libbead/part/registration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace bead::part {
namespace {

// An old bead (semi-axes 4 across, 1.5 up) on a flat bed, and a narrower
// new bead laid on it off its centre, the old bead's flanks showing either
// side; points 0.05 mm apart with 0.01 mm of noise.
struct Scene {
  SurfaceGrid below;
  std::vector<float> x, z;
};

double OldBead(double x) { return std::abs(x) < 4.0 ? 1.5 * std::sqrt(1.0 - x * x / 16.0) : 0.0; }

Scene MakeScene(double shift, bool bead_below = true) {
  Scene s;
  SurfaceRow row;
  row.x0_mm = -12.0, row.dx_mm = 0.05 / 8;
  for (double x = row.x0_mm; x <= 12.0; x += row.dx_mm)
    row.z_mm.push_back(static_cast<float>(bead_below ? OldBead(x) : 0.0));
  s.below = SurfaceGrid(std::move(row));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (double x = -10.0; x <= 10.0; x += 0.05) {
    const double u = (x - shift - 0.3) / 3.0;
    const double top = std::abs(u) < 1.0 ? 1.2 + 1.5 * std::sqrt(1.0 - u * u) : 0.0;
    s.x.push_back(static_cast<float>(x));
    s.z.push_back(static_cast<float>(std::max(bead_below ? OldBead(x - shift) : 0.0, top) + noise(rng)));
  }
  return s;
}

constexpr RegistrationScale kScale{0.06, 0.01, 0.05};

TEST(Registration, TrackedFromTheLastShiftItIsTheScansShiftWithinItsSigma) {
  const double truth = 0.137;
  const Scene s = MakeScene(truth);
  const double start = truth + 0.12;
  const Registration tracked = Register(s.x, s.z, s.below, kScale, {}, &start);
  const Registration scanned = Register(s.x, s.z, s.below, kScale, {}, nullptr);
  EXPECT_TRUE(tracked.tracked);
  EXPECT_FALSE(scanned.tracked);
  ASSERT_TRUE(tracked.constrained && scanned.constrained);
  EXPECT_NEAR(tracked.shift, truth, 2.0 * tracked.sigma);
  EXPECT_NEAR(scanned.shift, truth, 2.0 * scanned.sigma);
  EXPECT_NEAR(tracked.shift, scanned.shift, 2.0 * scanned.sigma);
  // A wall's sampling bounds both (spacing / sqrt 12).
  EXPECT_GE(tracked.sigma, 0.05 / std::sqrt(12.0) - 1e-12);
}

TEST(Registration, AStartOutsideTheWarmWindowIsScannedNotTracked) {
  const double truth = -0.4;
  const Scene s = MakeScene(truth);
  const double start = truth + 0.5;  // beyond the warm window's 0.3 mm
  const Registration r = Register(s.x, s.z, s.below, kScale, {}, &start);
  EXPECT_FALSE(r.tracked);
  ASSERT_TRUE(r.constrained);
  EXPECT_NEAR(r.shift, truth, 2.0 * r.sigma);
}

TEST(Registration, OnABareBedNothingIsTrackedOrConstrained) {
  const Scene s = MakeScene(0.2, false);
  const double start = 0.0;
  const Registration r = Register(s.x, s.z, s.below, kScale, {}, &start);
  EXPECT_FALSE(r.tracked);
  EXPECT_FALSE(r.constrained);
}

// A pass laid 4.2 mm off the one below, beyond the first range of +-3 mm
// (the surface below 24 mm wide: the widest range +-6). Found where it is
// whether the range widens because its least lies at its end or because
// the pass's first search looks over the widest; and tracked from there
// (part/registration.cc).
TEST(Registration, AShiftBeyondTheFirstRangeIsFoundWhereItIs) {
  const double truth = 4.2;
  const Scene s = MakeScene(truth);
  for (bool wide : {false, true}) {
    const Registration r = Register(s.x, s.z, s.below, kScale, {}, nullptr, nullptr, 0.0, wide);
    ASSERT_TRUE(r.constrained) << wide;
    EXPECT_NEAR(r.shift, truth, 2.0 * r.sigma) << wide;
  }
  const double start = truth - 0.1;
  const Registration tracked = Register(s.x, s.z, s.below, kScale, {}, &start);
  EXPECT_TRUE(tracked.tracked && tracked.constrained);
  EXPECT_NEAR(tracked.shift, truth, 2.0 * tracked.sigma);
}

// A box of half-width `half` and height h on a bed.
double Box(double x, double half, double h) { return std::abs(x) < half ? h : 0.0; }

// A layer below of one box 5 mm wide and 1.2 mm high, measured at points
// 0.05 mm apart with noise (0.01 mm).
SurfaceGrid BoxBelow(std::mt19937& rng, std::normal_distribution<double>& noise) {
  SurfaceRow row;
  row.x0_mm = -10.0, row.dx_mm = 0.05, row.at_points = true;
  for (int k = 0; k <= 400; ++k) row.z_mm.push_back(static_cast<float>(Box(-10.0 + 0.05 * k, 2.5, 1.2) + noise(rng)));
  row.variance.assign(row.z_mm.size(), 1.0f);
  return SurfaceGrid(std::move(row));
}

// That box moved by `shift` under a new one 5.2 mm wide and 3 mm high
// centred at `centre`, seen at the same points with the same noise.
void Covered(double shift, double centre, std::mt19937& rng, std::normal_distribution<double>& noise,
             std::vector<float>& x, std::vector<float>& z) {
  for (int k = 0; k <= 400; ++k) {
    const double xk = -10.0 + 0.05 * k;
    x.push_back(static_cast<float>(xk));
    z.push_back(static_cast<float>(std::max(Box(xk - shift, 2.5, 1.2), Box(xk - centre, 2.6, 3.0)) + noise(rng)));
  }
}

// A new bead that covers the one below, its walls beyond the old walls by
// 0.1 mm either side (a straight wall's beads, stacked): only the bare bed
// beside it speaks, and it says the old bead lies anywhere it stays hidden,
// a 0.2 mm bracket. The shift is somewhere in it, and its sigma says so:
// at least the bracket's uniform sigma (less the scan's quarter-spacing
// steps), the truth within two of it. (Counted as constrained by the few
// agreeing bed points whose noise slopes like a flank, the scan's least
// among the bracket's noise claimed a wall's sampling, 0.014 mm.)
TEST(Registration, ABeadCoveringTheOneBelowBracketsTheShift) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  const SurfaceGrid below = BoxBelow(rng, noise);
  const double truth = 0.03;
  std::vector<float> x, z;
  Covered(truth, truth, rng, noise, x, z);
  const double uniform = (0.2 - 0.025) / std::sqrt(12.0);
  for (const double* start : {static_cast<const double*>(nullptr), &truth}) {
    const Registration r = Register(x, z, below, kScale, {}, start, nullptr, start ? uniform : 0.0);
    EXPECT_GE(r.sigma, uniform) << (start ? "tracked" : "scanned");
    EXPECT_NEAR(r.shift, truth, 2.0 * r.sigma);
  }
}

// A new bead 2 mm wider than the one below, which lies anywhere in a 2 mm
// bracket, tracked from the pass's last least (no shift of the pass found:
// part/measure_part.cc searches about the profile before's least first).
// The warm window's scan (+-0.3 mm) lies inside the bracket; its sigma is
// the whole bracket's, not the window's (0.17 mm, where the window's scan
// was taken as it was).
TEST(Registration, ABracketWiderThanTheWarmWindowIsSearchedWhole) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  const SurfaceGrid below = BoxBelow(rng, noise);
  const double truth = 0.4, start = -0.2;
  std::vector<float> x, z;
  for (int k = 0; k <= 400; ++k) {
    const double xk = -10.0 + 0.05 * k;
    x.push_back(static_cast<float>(xk));
    z.push_back(static_cast<float>(std::max(Box(xk - truth, 2.5, 1.2), Box(xk, 3.5, 3.0)) + noise(rng)));
  }
  const Registration r = Register(x, z, below, kScale, {}, &start);
  EXPECT_FALSE(r.constrained);
  EXPECT_GE(r.sigma, (2.0 - 0.025) / std::sqrt(12.0));
  EXPECT_NEAR(r.shift, truth, 2.0 * r.sigma);
}

// The same covering bead, the surface below measured with the profile's
// noise at every point (a layer below scanned as this one is): over the
// bare bed either side, 3.4 % of its points rise by three noises over a
// spacing by chance. None of them is a flank: tracked from the truth (the
// pass's last shift) or searched, the shift is not counted as found.
// (Counted so, it was tracked as constrained at a wall's sampling, 0.014
// mm, wherever the track started in the bracket.)
TEST(Registration, ABareBedsNoiseIsNoFlankToRegisterOn) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  const SurfaceGrid below = BoxBelow(rng, noise);
  for (const double truth : {-0.07, 0.0, 0.05}) {
    std::vector<float> x, z;
    Covered(truth, 0.0, rng, noise, x, z);
    for (const double* start : {static_cast<const double*>(nullptr), &truth})
      EXPECT_FALSE(Register(x, z, below, kScale, {}, start).constrained) << truth << (start ? " tracked" : " searched");
  }
}

}  // namespace
}  // namespace bead::part
