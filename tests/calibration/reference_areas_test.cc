// Reference areas proposed from a run: they hold the bare surface and
// nothing else over the whole run, whatever the bead's wander, a rim at
// the field's side, the sensor's orientation or reflections.
#include "calibration/reference_areas.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <regex>

#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/profile/measure_block.h"
#include "libbead/sim/rig_simulator.h"
#include "tests/support/run_cli.h"

namespace bead::calibration {
namespace {

// A flat surface at z0 + slope x with a bead of half width w (a half
// ellipse of height H) centred at c, 0.1 mm apart over [-25, 25], the
// order reversed when asked (a sensor mounted the other way), a rim 2 mm
// high beyond x_rim.
struct Scene {
  double c = 0.0, w = 3.0, H = 2.0, z0 = 40.0, slope = 0.01, x_rim = 1e9;
  bool reversed = false;
};
void AddProfile(ReferenceSurveyor& s, const Scene& sc, std::mt19937_64& rng, double spike_prob = 0.0) {
  std::normal_distribution<float> noise(0.0f, 0.005f);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> x, z;
  for (int i = 0; i <= 500; ++i) {
    const double xi = -25.0 + 0.1 * i;
    const double t = (xi - sc.c) / sc.w;
    double h = std::abs(t) < 1.0 ? sc.H * std::sqrt(1.0 - t * t) : 0.0;
    if (xi > sc.x_rim) h += 2.0;
    if (u(rng) < spike_prob) h += 3.0;  // a reflection
    x.push_back(static_cast<float>(xi));
    z.push_back(static_cast<float>(sc.z0 + sc.slope * xi + h + noise(rng)));
  }
  if (sc.reversed) std::reverse(x.begin(), x.end()), std::reverse(z.begin(), z.end());
  s.Add(ProfileView{x, z, 0.0, 0});
}

// The bead wanders over +-2 mm: the areas begin a margin (1 mm) beyond its
// outermost edges (within a bin, 0.2 mm, of it) and run to the field's end.
TEST(ReferenceAreas, HoldTheBareSurfaceOverTheBeadsWander) {
  for (bool reversed : {false, true}) {
    ReferenceSurveyor s;
    std::mt19937_64 rng(3);
    for (int k = 0; k < 2000; ++k) {
      Scene sc;
      sc.c = 1.0 + 2.0 * std::sin(k * 0.01);
      sc.reversed = reversed;
      AddProfile(s, sc, rng, 0.002);
    }
    const ReferenceSurvey r = s.Propose();
    EXPECT_EQ(r.with_bead, 2000u);
    // Outermost edges: centre 1 -+ 2 -+ half width 3, halfway to the
    // bare point beyond (0.05 mm), within a spacing (0.1 mm).
    EXPECT_NEAR(r.bead_left_mm[0], -4.0, 0.1);
    EXPECT_NEAR(r.bead_right_mm[0], 6.0, 0.1);
    // The areas a margin (1 mm) beyond them, rounded out by up to two bins
    // (two spacings each).
    EXPECT_LE(r.left.area.x_max_mm, r.bead_left_mm[0] - 1.0);
    EXPECT_GE(r.left.area.x_max_mm, r.bead_left_mm[0] - 1.0 - 0.4);
    EXPECT_GE(r.right.area.x_min_mm, r.bead_right_mm[0] + 1.0);
    EXPECT_LE(r.right.area.x_min_mm, r.bead_right_mm[0] + 1.0 + 0.4);
    EXPECT_NEAR(r.left.area.x_min_mm, -25.0, 1e-4);
    EXPECT_NEAR(r.right.area.x_max_mm, 25.0, 1e-4);
    // Reflections (one point in 500) do not stand up.
    EXPECT_EQ(r.left.clear_fraction, 1.0);
    EXPECT_EQ(r.right.clear_fraction, 1.0);
    // An area the bead crosses part of the time is clear the rest of it:
    // [-3.5, -2.5] holds the bead while its centre is below 0.5 (plus a
    // bin of the area's rounding out, 0.2 mm).
    int inside = 0;
    for (int k = 0; k < 2000; ++k) inside += 1.0 + 2.0 * std::sin(k * 0.01) - 3.0 < -2.5 + 0.2;
    const double expected = 1.0 - inside / 2000.0;
    EXPECT_NEAR(s.ClearFraction({-3.5, -2.5}), expected, 0.1) << expected;
    EXPECT_LT(s.ClearFraction({-3.5, -2.5}), 0.7);
  }
}

TEST(ReferenceAreas, StopAtARimAndRefuseWhenNoRoomIsLeft) {
  ReferenceSurveyor s;
  std::mt19937_64 rng(4);
  Scene sc;
  sc.x_rim = 15.0;
  for (int k = 0; k < 300; ++k) AddProfile(s, sc, rng);
  const ReferenceSurvey r = s.Propose();
  // The last bare point is at 15.0 (the rim's first at 15.1): the area
  // ends within a bin (0.2 mm) before it.
  EXPECT_LE(r.right.area.x_max_mm, 15.0 + 1e-3);
  EXPECT_GE(r.right.area.x_max_mm, 15.0 - 0.2 - 1e-3);

  // A bead at the field's side (edge at 24 mm of 25) leaves no room
  // right of it for an area beyond the margin.
  ReferenceSurveyor aside;
  Scene off;
  off.c = 21.0;
  for (int k = 0; k < 300; ++k) AddProfile(aside, off, rng);
  try {
    aside.Propose();
    FAIL() << "no room for an area";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the bare surface right of the bead spans"), std::string::npos) << e.what();
  }
  // No bead at all: nothing to keep the areas away from.
  ReferenceSurveyor bare;
  Scene none;
  none.H = 0.0;
  for (int k = 0; k < 300; ++k) AddProfile(bare, none, rng);
  EXPECT_THROW(bare.Propose(), Error);
}

// The twin: a rig file without areas gets them from the run (bead
// calibrate reference -o), and the run measured with them loses no profile
// the simulator's own areas measure.
TEST(ReferenceCommand, ProposesAreasARigFileLacks) {
  test::TempDir dir;
  test::WriteText(dir / "sim.yaml", "seed: 9\nduration_s: 6\nsensor: {points: 256}\nbead: {center_wander_mm: 2.0}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  test::WriteText(dir / "bare.yaml",
                  "encoder: {counts_per_rev: 4096, bits: 32, direction: 1}\n"
                  "wheel: {diameter_mm: 254.762}\noffset: {counts: 3000}\n");
  const std::string run = dir / "twin/run.h5";
  auto [status, out] =
      test::RunCli(dir, "calibrate reference --rig " + (dir / "bare.yaml") + " " + run + " -o " + (dir / "rig.yaml"));
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("the rig file has no reference areas"), std::string::npos) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(clear_left=([0-9.]+)% clear_right=([0-9.]+)%)"))) << out;
  EXPECT_GE(std::stod(m[1]), 99.5) << out;
  EXPECT_GE(std::stod(m[2]), 99.5) << out;
  const RigFile written = ReadRigFile(dir / "rig.yaml");  // the areas now required: present
  EXPECT_LT(written.rig.reference_left.x_max_mm, written.rig.reference_right.x_min_mm);

  auto measure = [&](const std::string& rig) {
    auto [st, text] = test::RunCli(dir, "measure --occlusion none --rig " + rig + " " + run + " -o " + (dir / "g.csv"));
    EXPECT_EQ(st, 0) << text;
    std::smatch v;
    EXPECT_TRUE(std::regex_search(text, v, std::regex(R"(([0-9]+) valid)"))) << text;
    return v.size() > 1 ? std::stoi(v[1]) : -1;
  };
  EXPECT_GE(measure(dir / "rig.yaml"), measure(dir / "twin/rig.yaml"));
}

}  // namespace
}  // namespace bead::calibration
