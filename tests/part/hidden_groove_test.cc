// What an overhanging bead hides on a wall: the twin's beads (ellipses
// sunk into the layer below) hide the groove under their sides from a
// sensor looking down; the corrected area recovers the material laid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/part/measure_part.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

struct GrooveFigures {
  std::vector<double> visible_rel, corrected_rel, z;  // per profile
  double laid = 0.0, visible = 0.0, corrected = 0.0;
  int rows = 0, corrected_rows = 0;
};

GrooveFigures Figures(uint64_t seed, double exponent = 2.0, double area_mm2 = 12.0, double shadow_mm = 0.0,
                      double noise_mm = 0.01, double pass_shift_sigma_mm = 0.2) {
  sim::PartTwinConfig c;
  c.seed = seed;
  c.pass_shift_sigma_mm = pass_shift_sigma_mm;
  c.noise_mm = noise_mm;
  c.exponent = exponent;
  c.area_mm2 = area_mm2;
  c.shadow_mm = shadow_mm;
  const sim::PartTwin twin = sim::SimulatePartWall(c);
  ProfileStream stream("twin", twin.scan.profiles);
  GrooveFigures f;
  part::MeasurePart(stream, *twin.scan.part, twin.rig, {}, [&](const part::PartGeometryRow& r) {
    if (!r.bead.valid()) return;
    ++f.rows;
    const sim::PartTruthRow& t = twin.truth[r.profile];
    f.visible_rel.push_back(r.bead.area_mm2 / t.area_mm2 - 1.0);
    f.visible += r.bead.area_mm2, f.laid += t.area_mm2;
    if (!std::isfinite(r.area_corrected_mm2)) return;
    ++f.corrected_rows;
    f.corrected += r.area_corrected_mm2;
    f.corrected_rel.push_back(r.area_corrected_mm2 / t.area_mm2 - 1.0);
    f.z.push_back((r.area_corrected_mm2 - t.area_mm2) / r.area_corrected_sigma_mm2);
  });
  return f;
}

// The rows whose 95 % interval covers the material laid, and the fewest
// of n that calibrated intervals leave: 95 % less three binomial sigmas.
int Covered(const GrooveFigures& f) {
  int covered = 0;
  for (double z : f.z) covered += std::abs(z) < 1.96;
  return covered;
}
double CoverageFloor(std::size_t rows) {
  const double n = static_cast<double>(rows);
  return n * (0.95 - 3.0 * std::sqrt(0.05 * 0.95 / n));
}

using test::MedianAbs;

// Four walls the thresholds were not set on (seeds 5 to 8, the twin's
// default wall: six layers whose beads overhang the one below). The
// issue's bars for a wall: the material laid within 1 % over the run and
// 3 % per profile (median), where what the sensor sees is 15-23 % over;
// the corrected area's sigma a promise: its 95 % interval covers the
// material laid in at least 90 % of the profiles, pooled (4800 rows; their
// errors correlate along the path, so the band is not the binomial one of
// independent rows).
TEST(HiddenGroove, TheCorrectedAreaIsTheMaterialLaidWhereTheSeenAreaIsNot) {
  int covered = 0, rows = 0;
  double z2 = 0.0;
  for (uint64_t seed : {5u, 6u, 7u, 8u}) {
    const GrooveFigures f = Figures(seed);
    for (double z : f.z) covered += std::abs(z) < 1.96, z2 += z * z;
    rows += static_cast<int>(f.z.size());
    std::printf(
        "wall seed %llu: over the run seen %+.2f %%, corrected %+.2f %%; per profile median |error| seen "
        "%.2f %%, corrected %.2f %%\n",
        static_cast<unsigned long long>(seed), 100 * (f.visible / f.laid - 1), 100 * (f.corrected / f.laid - 1),
        100 * MedianAbs(f.visible_rel), 100 * MedianAbs(f.corrected_rel));
    EXPECT_EQ(f.corrected_rows, f.rows) << seed;
    EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01) << seed;
    EXPECT_LT(MedianAbs(f.corrected_rel), 0.03) << seed;
    EXPECT_GT(f.visible / f.laid - 1, 0.05) << seed << ": the wall hides nothing; the test says nothing";
  }
  std::printf("95 %% intervals covering the material laid: %d of %d, the errors' RMS over their sigmas %.2f\n", covered,
              rows, std::sqrt(z2 / rows));

  // Never over-confident (at least 90 %); and not so wide that it never
  // misses (at most 99.6 %: 19 misses of 4800). On these walls, the beads
  // placed at their silhouettes (part/silhouette.h), it covers 99.5 %, the
  // errors' RMS 0.63 of their sigmas: wider than these walls need. (98.2 %
  // while a foot could run on past a bare point onto the layer below's wall
  // interpolated across its cell, part/added_bead.h: the area seen gained
  // some 0.03 mm^2 on those rows, 60 of the 86 misses; 98.0 % before the
  // layer below's steps along the path were counted, part/surface_below.h
  // BelowChange; 95.4 % when this test was written, 96.4 % then with the
  // ellipse's exponent held, not pooled from the walls). (Fitted from eight
  // starts, 98.5 %, RMS 0.63. Placed at the silhouette with the area's
  // edges and the groove's ends counted apart, and the shift moving the
  // groove alone, 99.5 %: where the ends lie in their cells and where the
  // surface below lies move the area seen and the groove together.)
  EXPECT_GE(covered, 0.90 * rows);
  EXPECT_LE(covered, 0.996 * rows);
}

// Walls whose beads are no ellipses (the twin's beads superellipses, from
// toward a diamond to toward a box): the layer's exponent pooled from its
// walls, the same bars hold. (An ellipse taken for such beads corrected an
// independently generated wall by +17 % at p = 1.6 and -25 % at p = 2.5.)
// The diamond's whole outline holds 12.8 mm^2 at the twin's width and
// aspect: it lays 10 +- 2.
TEST(HiddenGroove, WallsOfAnotherShapeAreCorrectedWithTheirExponent) {
  for (auto [exponent, area] : {std::pair{1.6, 10.0}, std::pair{2.6, 12.0}}) {
    const GrooveFigures f = Figures(9, exponent, area);
    int covered = 0;
    for (double z : f.z) covered += std::abs(z) < 1.96;
    std::printf(
        "wall of exponent %.1f: over the run seen %+.2f %%, corrected %+.2f %%; per profile median |error| "
        "corrected %.2f %%; 95 %% intervals covering %d of %zu\n",
        exponent, 100 * (f.visible / f.laid - 1), 100 * (f.corrected / f.laid - 1), 100 * MedianAbs(f.corrected_rel),
        covered, f.z.size());
    EXPECT_EQ(f.corrected_rows, f.rows) << exponent;
    EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01) << exponent;
    EXPECT_LT(MedianAbs(f.corrected_rel), 0.03) << exponent;
    EXPECT_GE(covered, 0.90 * static_cast<double>(f.z.size())) << exponent;
    EXPECT_GT(f.visible / f.laid - 1, 0.05) << exponent << ": the wall hides nothing; the test says nothing";
  }
}

// Boxier beads (exponent 2.6) laid 1.5-4.4 mm off the one below (pass
// shifts of 1 mm sigma, seed 33): most rows of layers 1-3 show one wall,
// the other end sunk into the bead below, and are fitted, not placed at
// their walls. The fit holds the layer's exponent, and the layer's aspect
// is pooled over its rows placed at their walls: a fitted ellipse's aspect
// on these beads is 0.38-0.41 for 0.50. (With ellipses fitted and pooled,
// the wall was corrected 3.1 % low and 700 of 1200 intervals covered,
// none of layer 3's.)
TEST(HiddenGroove, BoxierBeadsHangingOffTheOneBelowAreFittedWithTheirExponent) {
  const GrooveFigures f = Figures(33, 2.6, 12.0, 0.0, 0.01, 1.0);
  const int covered = Covered(f);
  std::printf(
      "boxier beads off the one below: over the run seen %+.2f %%, corrected %+.2f %%; 95 %% intervals "
      "covering %d of %zu\n",
      100 * (f.visible / f.laid - 1), 100 * (f.corrected / f.laid - 1), covered, f.z.size());
  EXPECT_EQ(f.corrected_rows, f.rows);
  EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01);
  EXPECT_LT(MedianAbs(f.corrected_rel), 0.03);
  EXPECT_GE(covered, CoverageFloor(f.z.size()));
}

// Beads toward a diamond (exponent 1.6, 10 mm^2) laid off the one below
// by pass shifts of 1 mm sigma (seed 41): the last layer shows too few
// walls (under 10 of its first rows) to solve its own exponent, and holds
// the layers' below, fitting its rows with it. (With the ellipse assumed
// there, its aspect pooled 0.58 for 0.50, the layer came out 13 % high,
// none of its intervals covering: the wall +2.3 %, 998 of 1200.)
TEST(HiddenGroove, ALayerShowingTooFewWallsHoldsTheShapeOfTheLayersBelow) {
  const GrooveFigures f = Figures(41, 1.6, 10.0, 0.0, 0.01, 1.0);
  const int covered = Covered(f);
  std::printf(
      "diamonds, the last layer's exponent carried: over the run seen %+.2f %%, corrected %+.2f %%; 95 %% "
      "intervals covering %d of %zu\n",
      100 * (f.visible / f.laid - 1), 100 * (f.corrected / f.laid - 1), covered, f.z.size());
  EXPECT_EQ(f.corrected_rows, f.rows);
  EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01);
  EXPECT_GE(covered, CoverageFloor(f.z.size()));
}

// Beads sunk deep (6 mm^2 of a 14.1 mm^2 ellipse): on the bed their sides
// meet it, above they overhang less; where nothing is hidden the corrected
// area is the area seen, and its interval is the area seen's own (its
// points' noise, the surface below's): it still covers the material laid.
TEST(HiddenGroove, BeadsThatHideLittleKeepIntervalsThatCover) {
  const GrooveFigures f = Figures(10, 2.0, 6.0);
  int covered = 0;
  for (double z : f.z) covered += std::abs(z) < 1.96;
  std::printf(
      "sunk wall: over the run seen %+.2f %%, corrected %+.2f %%; per profile median |error| corrected %.2f %%; "
      "95 %% intervals covering %d of %zu\n",
      100 * (f.visible / f.laid - 1), 100 * (f.corrected / f.laid - 1), 100 * MedianAbs(f.corrected_rel), covered,
      f.z.size());
  EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01);
  EXPECT_GE(covered, 0.90 * static_cast<double>(f.z.size()));
}

// A profiler that loses the points beside each bead's right wall (a
// triangulation camera on the left: the bead hides the surface next to it;
// 0.15 mm, three points): each layer's wall rises across the gap, the
// layer below carries the same gap. The bars hold and the intervals
// stay honest. (Each end placed at its gap's middle and the layer below
// bridged as a ramp, these walls were +2.71 and +2.31 % over the run, 342
// of 2400 intervals covering.)
TEST(HiddenGroove, AShadowBesideEachWallKeepsTheBarsAndTheIntervals) {
  int covered = 0, rows = 0;
  for (uint64_t seed : {41u, 42u}) {
    const GrooveFigures f = Figures(seed, 2.0, 12.0, 0.15);
    for (double z : f.z) covered += std::abs(z) < 1.96;
    rows += static_cast<int>(f.z.size());
    std::printf("shadowed wall seed %llu: over the run corrected %+.2f %%, per profile median |error| %.2f %%\n",
                static_cast<unsigned long long>(seed), 100 * (f.corrected / f.laid - 1),
                100 * MedianAbs(f.corrected_rel));
    EXPECT_EQ(f.corrected_rows, f.rows) << seed;
    EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01) << seed;
    EXPECT_LT(MedianAbs(f.corrected_rel), 0.03) << seed;
  }
  std::printf("shadowed walls: 95 %% intervals covering %d of %d\n", covered, rows);
  EXPECT_GE(covered, static_cast<int>(0.85 * rows));
}

// A finer sensor: 1 um of noise (read at the 2 um floor of
// part/added_bead.h). The model's shapes leave 4-7 um on the twin's tops
// whatever the noise (hidden_groove.h: kTopShapeHeights); judged against
// the noise alone, four of six layers of seed 1 were refused as none of the
// model's shapes and stood 15-30 % high. Every row is corrected and the
// bars hold (seed 1 and 2).
TEST(HiddenGroove, AFinerSensorsWallIsCorrectedInEveryLayer) {
  for (uint64_t seed : {1u, 2u}) {
    const GrooveFigures f = Figures(seed, 2.0, 12.0, 0.0, 0.001);
    std::printf("1 um wall seed %llu: %d of %d rows corrected, over the run %+.2f %%, per profile median %.2f %%\n",
                static_cast<unsigned long long>(seed), f.corrected_rows, f.rows, 100 * (f.corrected / f.laid - 1),
                100 * MedianAbs(f.corrected_rel));
    EXPECT_EQ(f.corrected_rows, f.rows) << seed;
    EXPECT_LT(std::abs(f.corrected / f.laid - 1), 0.01) << seed;
    EXPECT_LT(MedianAbs(f.corrected_rel), 0.03) << seed;
  }
}

// A bead whose top the model's shapes cannot follow in some rows: every
// fourth row of the twin's default wall (layers 1-5) carries a bump on its
// top (a Gaussian 0.12 mm high, 0.4 mm sigma, 1 mm right of the bead's
// centre: 0.12 mm^2 of material, counted in the truth), as a fold or a
// blob of melt would leave. The shape placed on such a row misses its top
// by several times what a top may leave (hidden_groove.h: TopTolerance),
// and the row's sigma says how far that moves its outline: the bumped
// rows' 95 % intervals cover as the others' do.
TEST(HiddenGroove, ARowWhoseTopTheShapeMissesHasASigmaThatHoldsIt) {
  sim::PartTwinConfig c;
  c.seed = 9;
  sim::PartTwin twin = sim::SimulatePartWall(c);
  ProfileBlock& b = twin.scan.profiles;
  const PartPlaces& places = *twin.scan.part;
  constexpr double kHeight = 0.12, kSigma = 0.4, kRight = 1.0;
  std::vector<bool> bumped(b.size(), false);
  for (std::size_t i = 0; i < b.size(); ++i) {
    sim::PartTruthRow& t = twin.truth[i];
    if (t.layer == 0 || i % 4 != 0) continue;
    bumped[i] = true;
    t.area_mm2 += kHeight * kSigma * std::sqrt(2.0 * M_PI);
    for (std::size_t j = 0; j < b.points; ++j) {
      const double u = (b.view(i).x_mm[j] + places.frame_x_mm[i] - t.center_x_mm - kRight) / kSigma;
      if (std::abs(u) < 4.0) b.z_mm[i * b.points + j] += static_cast<float>(kHeight * std::exp(-0.5 * u * u));
    }
  }
  ProfileStream stream("twin", twin.scan.profiles);
  int rows[2] = {0, 0}, covered[2] = {0, 0};
  double z2[2] = {0.0, 0.0};
  part::MeasurePart(stream, places, twin.rig, {}, [&](const part::PartGeometryRow& r) {
    if (!r.bead.valid() || r.layer == 0 || !std::isfinite(r.area_corrected_mm2)) return;
    const double z = (r.area_corrected_mm2 - twin.truth[r.profile].area_mm2) / r.area_corrected_sigma_mm2;
    const int k = bumped[r.profile] ? 1 : 0;
    ++rows[k], covered[k] += std::abs(z) <= 1.96, z2[k] += z * z;
  });
  std::printf("bumped tops: 95 %% intervals covering %d of %d bumped rows (RMS z %.2f), %d of %d others (%.2f)\n",
              covered[1], rows[1], std::sqrt(z2[1] / rows[1]), covered[0], rows[0], std::sqrt(z2[0] / rows[0]));
  EXPECT_GT(rows[1], 0.9 * 250);  // of the 250 bumped rows
  EXPECT_GE(covered[1], 0.90 * rows[1]);
  EXPECT_GE(covered[0], 0.90 * rows[0]);
}

}  // namespace
}  // namespace bead
