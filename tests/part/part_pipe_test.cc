// A wall laid along a pipe (part: {bed: cylinder}): the first layer is
// measured against the arc through the bare pipe either side, its radius
// given or fitted, wherever the bead wandered on the slope; a line through
// the same bare surface (a flat bed assumed) counts the pipe's crown.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/part/bed_arc.h"
#include "libbead/part/measure_part.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

// Layer 0's area error against the twin's visible area, over its valid
// profiles; `not_a_line`: how many were refused for reference areas that
// are no line (AddedStatus::kReferenceNotALine).
std::vector<double> FirstLayerErrors(const sim::PartTwin& twin, const Rig& rig, int* not_a_line = nullptr) {
  ProfileStream stream("pipe", twin.scan.profiles);
  std::vector<double> e;
  part::MeasurePart(stream, *twin.scan.part, rig, {}, [&](const part::PartGeometryRow& r) {
    if (r.layer == 0 && r.bead.valid()) e.push_back(r.bead.area_mm2 - twin.truth[r.profile].visible_area_mm2);
    if (not_a_line) *not_a_line += r.bead.status == part::AddedStatus::kReferenceNotALine;
  });
  return e;
}

using test::Rms;

TEST(PartPipe, TheFirstLayerStandsOnTheArcGivenOrFittedNotOnAChord) {
  sim::PartTwinConfig config;
  config.layers = 1;
  config.length_mm = 40.0;
  config.bed_radius_mm = 60.0;
  config.wander_sigma_mm = 2.0;  // off the crest, onto the slope
  config.seed = 31;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  Rig given = twin.rig, fitted = twin.rig, flat = twin.rig;
  fitted.part->radius_mm = 0.0;
  flat.part = PartBed{};
  int not_a_line = 0;
  const std::vector<double> e_given = FirstLayerErrors(twin, given), e_fitted = FirstLayerErrors(twin, fitted),
                            e_flat = FirstLayerErrors(twin, flat, &not_a_line);
  ASSERT_EQ(e_given.size(), twin.truth.size());
  ASSERT_EQ(e_fitted.size(), twin.truth.size());
  // Within the wall test's bound (0.15 mm^2: walls known to a spacing).
  EXPECT_LT(Rms(e_given), 0.15);
  EXPECT_LT(Rms(e_fitted), 0.15);
  // The chord between the bare areas lies under the pipe's crown by the
  // sagitta s = R - sqrt(R^2 - 20^2) = 3.43 mm; within 7 mm of the crest
  // (the bead's half width and two wander sigmas) the arc falls by at most
  // 7^2 / 2R = 0.41 mm: under the bead alone a line counts at least
  // width (s - 0.41) of pipe as bead (it did, before the line was judged).
  // A flat bed assumed on the pipe: its reference areas, 5 mm of arc each,
  // are no line to the noise (a chord over 5 mm of R = 60 leaves the arc
  // 5^2 / 8R = 52 um off at its middle, five noises), and no profile is
  // measured over the chord.
  EXPECT_TRUE(e_flat.empty()) << "a flat bed assumed on a pipe";
  EXPECT_EQ(not_a_line, static_cast<int>(twin.truth.size()));
}

TEST(PartPipe, TheArcIsFoundThroughNoiseAndItsRadiusWhenNotGiven) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<float> x, z;
  const double r = 60.0, xc = 1.5, zc = -59.0;
  for (double u = -20.0; u <= 20.0; u += 0.05) {
    x.push_back(static_cast<float>(u));
    z.push_back(static_cast<float>(zc + std::sqrt(r * r - (u - xc) * (u - xc)) + noise(rng)));
  }
  const ReferenceArea left{-20.0, -15.0}, right{15.0, 20.0};
  const part::BedArc given = part::FitBedArc(x, z, left, right, r);
  ASSERT_TRUE(given.ok) << given.why;
  EXPECT_NEAR(given.xc_mm, xc, 0.05);
  EXPECT_NEAR(given.zc_mm, zc, 0.05);
  EXPECT_NEAR(given.rms_mm, 0.01, 0.003);
  const part::BedArc fitted = part::FitBedArc(x, z, left, right, 0.0);
  ASSERT_TRUE(fitted.ok) << fitted.why;
  // Two 5 mm arcs 30 mm apart, 0.01 mm of noise: the radius to about 1 %.
  EXPECT_NEAR(fitted.radius_mm, r, 0.02 * r);
  // At the crest, where the bead stands, the arc within a few noise sigmas.
  EXPECT_NEAR(fitted.At(xc), zc + r, 0.03);
  // Too little bare bed is said.
  const part::BedArc none = part::FitBedArc(x, z, {-30.0, -29.0}, {29.0, 30.0}, 0.0);
  EXPECT_FALSE(none.ok);
  EXPECT_NE(none.why.find("fewer than 10 points"), std::string::npos);
}

}  // namespace
}  // namespace bead
