// Several beads in one profile: a layer of roads laid side by side by the
// twin (ellipses, each sunk into the surface the roads before it left: a
// shape the arcs of part/roads.h do not hold exactly), scanned after the
// layer. Each road's count, centre and material against the twin's truth,
// beside the naive split by a vertical cut at the valley.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/road_arcs.h"
#include "libbead/part/roads.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/scaled_twin.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

std::vector<part::PartGeometryRow> MeasureRoads(const sim::PartTwin& twin) {
  ProfileStream stream("twin", twin.scan.profiles);
  part::MeasurePartOptions options;
  options.several_beads = true;
  std::vector<part::PartGeometryRow> rows;
  part::MeasurePart(stream, *twin.scan.part, twin.rig, options,
                    [&](const part::PartGeometryRow& r) { rows.push_back(r); });
  return rows;
}

using test::Median;

struct RoadFigures {
  int profiles = 0, counted_right = 0;
  double center_error_max = 0.0;                     // mm, over every road counted right
  std::vector<double> area_error, naive_area_error;  // relative, per road
  std::vector<double> area_sum_error;                // relative, per profile
  std::vector<double> spacing_over_width;
};

// The single road's width on the bed (the overlap models' w): the twin's
// first road, laid on the bare bed.
double LoneWidth(sim::PartTwinConfig c) {
  c.roads = 2, c.road_spacing_mm = 3.0 * c.width_mm, c.field_half_mm = 2.5 * c.width_mm + 6.0;
  c.area_wave_mm2 = 0.0, c.wander_sigma_mm = 0.0, c.length_mm = 1.0;
  return sim::SimulateRoadLayer(c).road_truth.front().width_mm;
}

// k: the layer at k times its size (tests/support/scaled_twin.h).
RoadFigures RoadsAt(double spacing_over_width, uint64_t seed, double k = 1.0) {
  sim::PartTwinConfig c;
  c.layers = 1, c.roads = 4, c.length_mm = 60.0, c.seed = seed, c.wander_sigma_mm = 0.05;
  c.area_mm2 = 6.0, c.area_wave_mm2 = 0.6;
  c = test::Scaled(c, k);
  c.road_spacing_mm = spacing_over_width * LoneWidth(c);
  c.field_half_mm = 1.5 * c.road_spacing_mm + 0.5 * c.width_mm + 7.0;
  const sim::PartTwin twin = sim::SimulateRoadLayer(c);
  RoadFigures f;
  for (const part::PartGeometryRow& row : MeasureRoads(twin)) {
    ++f.profiles;
    const auto truth = twin.road_truth.begin() + static_cast<std::ptrdiff_t>(row.profile * c.roads);
    if (row.roads.size() != static_cast<std::size_t>(c.roads)) continue;
    ++f.counted_right;
    double sum = 0.0, true_sum = 0.0;
    for (int k = 0; k < c.roads; ++k) {
      const part::Road& r = row.roads[k];
      const sim::PartRoadTruth& t = truth[k];
      f.center_error_max = std::max(f.center_error_max, std::abs(r.center_x_mm - t.center_x_mm));
      f.area_error.push_back(r.area_mm2 / t.area_mm2 - 1.0);
      f.naive_area_error.push_back(t.naive_area_mm2 / t.area_mm2 - 1.0);
      if (k > 0) f.spacing_over_width.push_back(r.spacing_over_width);
      sum += r.area_mm2, true_sum += t.area_mm2;
    }
    f.area_sum_error.push_back(sum / true_sum - 1.0);
  }
  return f;
}

using test::MedianAbs;

// The figures on the twin (ellipses laid in order, each filling
// down to the surface before it), seeds the thresholds were not set on.
TEST(Roads, EachRoadOfALayerIsCountedPlacedAndGivenItsMaterial) {
  for (double ratio : {0.70, 0.85, 1.05}) {
    const RoadFigures f = RoadsAt(ratio, 31);
    std::printf(
        "spacing %.2f w: counted right %d of %d, centre error at most %.3f mm, road area |error| median %.2f %% "
        "(vertical cut at the valley %.2f %%), spacing/w median %.3f\n",
        ratio, f.counted_right, f.profiles, f.center_error_max, 100 * MedianAbs(f.area_error),
        100 * MedianAbs(f.naive_area_error), Median(f.spacing_over_width));
    EXPECT_GE(f.counted_right, (ratio < 0.8 ? 0.90 : 0.95) * f.profiles) << ratio;
    EXPECT_LE(f.center_error_max, 0.3) << ratio;
    if (ratio > 0.8) {
      EXPECT_LE(MedianAbs(f.area_error), 0.05) << ratio;
    }
    // The roads' areas add up to what was measured: the split moves
    // material between roads, never makes or loses it.
    EXPECT_LE(std::abs(Median(f.area_sum_error)), 0.01) << ratio;
    EXPECT_NEAR(Median(f.spacing_over_width), ratio, 0.05) << ratio;
  }
}

// The same roads at a quarter of the twin's size (1.5 mm wide, 0.35 mm
// high, points 12.5 um apart with 2.5 um of noise) and four times it: the
// same figures, the centres' bound scaled. A quarter the size, crests
// were told from valleys by the detection threshold's floor (0.05 mm, of
// valleys 0.08-0.11 mm deep at 0.7 w) after smoothing over +-0.15 mm (a
// tenth of a road, which shallows them further): at 0.70 w the four roads
// were counted in 41 of 120 profiles.
TEST(Roads, RoadsAQuarterAndFourTimesTheTwinsSizeAreCountedAsTheTwinsAre) {
  for (double k : {0.25, 4.0}) {
    for (double ratio : {0.70, 0.85}) {
      const RoadFigures f = RoadsAt(ratio, 31, k);
      std::printf(
          "%.2f times the size, spacing %.2f w: counted right %d of %d, centre error at most %.4f mm, road "
          "area |error| median %.2f %%\n",
          k, ratio, f.counted_right, f.profiles, f.center_error_max, 100 * MedianAbs(f.area_error));
      EXPECT_GE(f.counted_right, (ratio < 0.8 ? 0.90 : 0.95) * f.profiles) << k << " " << ratio;
      EXPECT_LE(f.center_error_max, 0.3 * k) << k << " " << ratio;
      if (ratio > 0.8) {
        EXPECT_LE(MedianAbs(f.area_error), 0.05) << k << " " << ratio;
      }
      EXPECT_NEAR(Median(f.spacing_over_width), ratio, 0.05) << k << " " << ratio;
    }
  }
}

// Another generator than the twin's: parabolic roads (the overlap models'
// shape) laid in order, each raised until it adds its area over the surface
// the ones before it left; 0.01 mm of noise on 0.05 mm points.
struct ParabolicLayer {
  std::vector<float> x;
  std::vector<double> gain, area, center;
};

ParabolicLayer Parabolas(int roads, double spacing_over_width, double width, double area, uint64_t seed) {
  ParabolicLayer p;
  const double half = 0.5 * width, step = spacing_over_width * width;
  for (double x = -(roads * step + 2 * width); x <= roads * step + 2 * width; x += 0.05) p.x.push_back(float(x));
  std::vector<double> surface(p.x.size(), 0.0);
  for (int k = 0; k < roads; ++k) {
    const double c = (k - 0.5 * (roads - 1)) * step, a = area * (1.0 + 0.05 * k);
    auto added = [&](double z0, std::vector<double>* out) {
      double sum = 0.0;
      for (std::size_t j = 0; j < p.x.size(); ++j) {
        const double u = (p.x[j] - c) / half;
        const double top = std::abs(u) < 1 ? z0 + 1.5 * a / width * (1 - u * u) : -1e9;
        sum += std::max(0.0, top - surface[j]) * 0.05;
        if (out) (*out)[j] = std::max(surface[j], top);
      }
      return sum;
    };
    double lo = -5, hi = 5;
    for (int it = 0; it < 60; ++it) (added(0.5 * (lo + hi), nullptr) < a ? lo : hi) = 0.5 * (lo + hi);
    added(0.5 * (lo + hi), &surface);
    p.area.push_back(a), p.center.push_back(c);
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (double z : surface) p.gain.push_back(z + noise(rng));
  return p;
}

TEST(Roads, ParabolicRoadsOfAnotherGeneratorAreSplitWithinFivePercent) {
  for (double ratio : {0.70, 0.85, 1.05}) {
    int right = 0, tries = 0;
    std::vector<double> area_error;
    double center_error = 0.0;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      const ParabolicLayer p = Parabolas(3, ratio, 6.0, 6.0, seed);
      const std::vector<part::Road> roads = part::FindRoads(p.x, p.gain, 0.01);
      ++tries;
      if (roads.size() != p.area.size()) continue;
      ++right;
      for (std::size_t k = 0; k < roads.size(); ++k) {
        area_error.push_back(roads[k].area_mm2 / p.area[k] - 1.0);
        center_error = std::max(center_error, std::abs(roads[k].center_x_mm - p.center[k]));
      }
    }
    std::printf(
        "parabolas at %.2f w: counted right %d of %d, centre error at most %.3f mm, area |error| median %.2f %%\n",
        ratio, right, tries, center_error, 100 * MedianAbs(area_error));
    EXPECT_GE(right, (ratio < 0.8 ? 0.90 : 0.95) * tries) << ratio;
    EXPECT_LE(center_error, 0.3) << ratio;
    if (ratio > 0.8) {
      EXPECT_LE(MedianAbs(area_error), 0.05) << ratio;
    }
  }
}

// The later road sits on the earlier one's flank and keeps the material in
// the valley; the naive vertical cut hands it to the earlier road.
TEST(Roads, TheLaterRoadKeepsTheValleysMaterialWhereAVerticalCutGivesItAway) {
  const RoadFigures f = RoadsAt(0.70, 5);
  ASSERT_FALSE(f.area_error.empty());
  EXPECT_LT(MedianAbs(f.area_error), 0.5 * MedianAbs(f.naive_area_error));
}

TEST(Roads, ARoadCutByTheFieldOfViewIsFlaggedNotMeasuredAsWhole) {
  ParabolicLayer p = Parabolas(3, 0.9, 6.0, 6.0, 3);
  // The field of view ends 1 mm past the first road's centre.
  const float edge = float(p.center.front() + 1.0);
  std::vector<float> x;
  std::vector<double> gain;
  for (std::size_t j = 0; j < p.x.size(); ++j)
    if (p.x[j] >= edge) x.push_back(p.x[j]), gain.push_back(p.gain[j]);
  const std::vector<part::Road> roads = part::FindRoads(x, gain, 0.01);
  ASSERT_FALSE(roads.empty());
  EXPECT_EQ(roads.front().status, part::RoadStatus::kCutByEdge);
  EXPECT_TRUE(roads.back().valid());
}

TEST(Roads, LaidRightToLeftTheMirroredLayerGivesTheMirroredSplit) {
  const ParabolicLayer p = Parabolas(3, 0.8, 6.0, 6.0, 9);
  std::vector<float> mx(p.x.rbegin(), p.x.rend());
  for (float& v : mx) v = -v;
  const std::vector<double> md(p.gain.rbegin(), p.gain.rend());
  part::RoadOptions right_first;
  right_first.laid_left_first = false;
  const std::vector<part::Road> a = part::FindRoads(p.x, p.gain, 0.01), b = part::FindRoads(mx, md, 0.01, right_first);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(a[k].area_mm2, b[a.size() - 1 - k].area_mm2, 1e-6);
    EXPECT_NEAR(a[k].center_x_mm, -b[a.size() - 1 - k].center_x_mm, 1e-6);
  }
  // ... and the same spacings, each pair's held by the road laid after
  // the other, the summary taking every pair in either order (right to
  // left it took the pairs' left roads' and the last road's NaN: two of
  // three pairs).
  part::RoadsSummary left, right;
  left.Add(a, true), right.Add(b, false);
  EXPECT_EQ(left.spacing_over_width.seen(), a.size() - 1);
  EXPECT_EQ(right.spacing_over_width.seen(), a.size() - 1);
  EXPECT_NEAR(left.MedianSpacing(), right.MedianSpacing(), 1e-6);
}

// The model's top is the highest cap whichever road was laid first, so the
// profile cannot show the order: each road's area in the other order is
// the split the other order's own run gives (the same fit, split the other
// way), and the summary says how much the split rests on it.
TEST(Roads, TheOtherOrdersAreaIsWhatThatOrderGivesAndTheSummarySaysIt) {
  part::RoadOptions right_first;
  right_first.laid_left_first = false;
  part::RoadsSummary overlapping, apart;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const ParabolicLayer p = Parabolas(3, 0.7, 6.0, 6.0, seed);
    const std::vector<part::Road> a = part::FindRoads(p.x, p.gain, 0.01),
                                  b = part::FindRoads(p.x, p.gain, 0.01, right_first);
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 3u);
    // The two fits differ by the solver's convergence only (the mirrored
    // profile's): far under the noise's 0.1 % of an area.
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_NEAR(a[k].area_other_order_mm2, b[k].area_mm2, 1e-3) << seed << " " << k;
      EXPECT_NEAR(b[k].area_other_order_mm2, a[k].area_mm2, 1e-3) << seed << " " << k;
    }
    // At 0.7 w the valley's material changes hands: the outer roads' areas
    // move by far more than the noise.
    EXPECT_GT(std::abs(a.front().area_other_order_mm2 / a.front().area_mm2 - 1.0), 0.02);
    overlapping.Add(a, true);
    const ParabolicLayer q = Parabolas(3, 1.05, 6.0, 6.0, seed);
    apart.Add(part::FindRoads(q.x, q.gain, 0.01), true);
  }
  EXPECT_NE(overlapping.OrderInWords(true).find("cannot show the order"), std::string::npos);
  EXPECT_NE(overlapping.OrderInWords(true).find("laid right to left"), std::string::npos);
  EXPECT_NE(apart.OrderInWords(true).find("do not rest on the order"), std::string::npos);
}

// The scan's summary keeps a bounded sample: at most kSize values however
// many rows, the quantiles of a long stream within their rank error
// (1 / sqrt(kSize) = 0.4 %: checked at five of it), the same stream the
// same sample, and a short stream's quantiles its own exactly.
TEST(Reservoir, AScansSummaryKeepsABoundedSampleWithTheStreamsQuantiles) {
  Reservoir a, b, small;
  const std::size_t n = 1'000'000;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = static_cast<double>(i) / static_cast<double>(n);  // in order: the hardest for a first-n sample
    a.Add(v), b.Add(v);
  }
  EXPECT_EQ(a.seen(), n);
  const double rank_error = 1.0 / std::sqrt(static_cast<double>(Reservoir::kSize));
  EXPECT_NEAR(a.Quantile(0.5), 0.5, 5 * rank_error);
  EXPECT_NEAR(a.Quantile(0.95), 0.95, 5 * rank_error);
  EXPECT_EQ(a.Quantile(0.5), b.Quantile(0.5));
  for (double v : {3.0, 1.0, 2.0, 5.0, 4.0}) small.Add(v);
  EXPECT_EQ(small.Quantile(0.5), 3.0);
  EXPECT_EQ(small.Quantile(0.95), 5.0);
  EXPECT_TRUE(std::isnan(Reservoir().Quantile(0.5)));
}

}  // namespace
}  // namespace bead
