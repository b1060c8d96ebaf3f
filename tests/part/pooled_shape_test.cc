// A layer's pooled bead shape (part/layer_grooves.h) is a printed promise:
// `bead measure` says each layer's aspect and exponent with their sigmas,
// and every row of the layer is corrected with them, so one pool's error
// is shared by the whole layer. Over many seeded twin walls, each layer's
// pool lies within two of its sigmas of the shape laid about as often as
// a 95 % interval should, its two errors correlated as it says; and a
// layer too short to reach kPoolProfiles is pooled at its end, not left to
// each row's own shape.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/part/layer_grooves.h"
#include "libbead/part/measure_part.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

struct PoolErrors {
  std::vector<double> aspect_z, exponent_z;  // (pooled - laid) / sigma, per layer
  std::vector<double> correlation;           // the pool's, per layer
  int layers = 0, pooled = 0;
};

// The twin's wall measured: each layer's brief.
std::vector<part::LayerSummary> Layers(const sim::PartTwinConfig& c) {
  const sim::PartTwin twin = sim::SimulatePartWall(c);
  ProfileStream stream("twin", twin.scan.profiles);
  return part::MeasurePart(stream, *twin.scan.part, twin.rig, {}, [](const part::PartGeometryRow&) {});
}

void AddWall(const sim::PartTwinConfig& c, PoolErrors& e) {
  for (const part::LayerSummary& l : Layers(c)) {
    ++e.layers;
    if (!l.shape) continue;
    ++e.pooled;
    e.aspect_z.push_back((l.shape->aspect - c.aspect) / l.shape->aspect_sigma);
    if (l.shape->exponent_sigma > 0.0)
      e.exponent_z.push_back((l.shape->exponent - c.exponent) / l.shape->exponent_sigma);
    e.correlation.push_back(l.shape->correlation);
  }
}

int Within(const std::vector<double>& z, double k) {
  int n = 0;
  for (double v : z) n += std::abs(v) <= k;
  return n;
}

using test::Rms;

// Twelve walls of six layers (72 pools, the seeds the thresholds were not
// set on). A 95 % interval misses 3.6 of 72 on average; 11 or more misses
// has a binomial probability under 1e-4 (the layers' pools are independent
// draws: each layer's beads, wander and shift drawn anew), so at least 61
// of 72 within two sigmas. The errors' RMS over their sigmas near 1: an
// interval twice as wide as it should be passes the count too, so the RMS
// must exceed a half.
TEST(PooledShape, EachLayersPoolLiesWithinItsSigmasOfTheShapeLaid) {
  PoolErrors e;
  for (uint64_t seed = 61; seed < 73; ++seed) {
    sim::PartTwinConfig c;
    c.seed = seed;
    AddWall(c, e);
  }
  ASSERT_EQ(e.pooled, e.layers);
  ASSERT_EQ(e.aspect_z.size(), 72u);
  ASSERT_EQ(e.exponent_z.size(), 72u);
  const int aspect_in = Within(e.aspect_z, 1.96), exponent_in = Within(e.exponent_z, 1.96);
  std::printf("pooled shapes within two sigmas: aspect %d of 72 (RMS %.2f), exponent %d of 72 (RMS %.2f)\n", aspect_in,
              Rms(e.aspect_z), exponent_in, Rms(e.exponent_z));
  EXPECT_GE(aspect_in, 61);
  EXPECT_GE(exponent_in, 61);
  EXPECT_GT(Rms(e.aspect_z), 0.5);
  EXPECT_GT(Rms(e.exponent_z), 0.5);
  // The two errors move together (a bead solved boxier is solved with
  // another aspect), and the correlation each pool carries, its rows', is
  // not less than theirs: less, the corrected area's sigma would miss what
  // the two errors move together. (A sample correlation r of 72 pairs has
  // a standard error of about (1 - r^2) / sqrt(72).)
  double zz = 0.0, carried = 0.0;
  for (std::size_t k = 0; k < 72; ++k) zz += e.aspect_z[k] * e.exponent_z[k], carried += e.correlation[k] / 72;
  const double r = zz / 72 / Rms(e.aspect_z) / Rms(e.exponent_z), se = (1 - r * r) / std::sqrt(72.0);
  std::printf("the pools' errors' correlation %.2f (standard error %.2f), the rows' each pool carries %.2f\n", r, se,
              carried);
  EXPECT_GT(r, 3 * se);
  EXPECT_GT(carried, r - 3 * se);
}

// A wall whose layers hold fewer profiles than the pool waits for (a short
// part, a coarse scan): each layer still pools its shape, at its end, and
// its rows are corrected with it.
TEST(PooledShape, ALayerShorterThanThePoolIsPooledAtItsEnd) {
  sim::PartTwinConfig c;
  c.seed = 3;
  c.layers = 3;
  c.length_mm = 0.5 * 0.6 * static_cast<double>(part::LayerGrooves::kPoolProfiles);  // 60 % of a pool's profiles
  PoolErrors e;
  AddWall(c, e);
  EXPECT_EQ(e.layers, 3);
  EXPECT_EQ(e.pooled, 3) << "a short layer's rows went out with their own shapes";
}

// A pool whose aspect is known loosely after kPoolProfiles rows (a coarse,
// noisy profiler: 0.1 mm between points, 30 um of noise) gathers more rows,
// until its sigma is within kLoosePool of it or kMaxWaiting rows wait; on
// the twin's own wall (0.05 mm, 10 um) every layer pools on kPoolProfiles.
TEST(PooledShape, ALoosePoolGathersMoreRows) {
  using part::LayerGrooves;
  sim::PartTwinConfig c;
  c.seed = 5;
  c.layers = 4;
  c.length_mm = 150.0;  // 300 profiles a layer
  for (const part::LayerSummary& l : Layers(c)) {
    ASSERT_TRUE(l.shape) << l.layer;
    EXPECT_EQ(l.shape->rows, LayerGrooves::kPoolProfiles) << l.layer;
  }
  c.point_spacing_mm = 0.1;
  c.noise_mm = 0.03;
  int gathered = 0;
  for (const part::LayerSummary& l : Layers(c)) {
    ASSERT_TRUE(l.shape) << l.layer;
    const part::PooledShape& s = *l.shape;
    std::printf("coarse layer %lld: pooled on %zu rows, aspect %.3f +- %.3f\n", static_cast<long long>(l.layer), s.rows,
                s.aspect, s.aspect_sigma);
    EXPECT_GE(s.rows, LayerGrooves::kPoolProfiles) << l.layer;
    if (s.rows > LayerGrooves::kPoolProfiles) ++gathered;
    // Loose only where the queue filled (a few of its rows with no shape
    // of their own: since the last check, under kLooseStep rows short).
    EXPECT_TRUE(s.aspect_sigma <= LayerGrooves::kLoosePool * s.aspect ||
                s.rows + LayerGrooves::kLooseStep >= LayerGrooves::kMaxWaiting)
        << l.layer << ": " << s.rows << " rows";
  }
  EXPECT_GT(gathered, 0) << "no pool was loose: the test says nothing";
}

}  // namespace
}  // namespace bead
