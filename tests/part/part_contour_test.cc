// A contour with rounded corners, six layers, printed by the twin: the head
// slows into each corner with the extruder's flow unchanged, so the bead
// bulges there (the thesis, 1.3.2). The bars for such a wall, on
// seeds the thresholds were not set on, beside the naive subtraction of
// the layer below as recorded that counts what it sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/part/layer_grooves.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_flow.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

struct ContourFigures {
  double laid = 0.0, measured = 0.0;
  std::vector<double> area_rel, height_error;
  std::vector<double> first_rel;  // of each layer's first rows (those its groove shape is pooled on)
  std::vector<double> flow, true_flow;
  part::CornerBulge bulge;
};

ContourFigures Figures(const sim::PartTwin& twin, bool naive) {
  ProfileStream stream("twin", twin.scan.profiles);
  part::MeasurePartOptions options;
  options.register_layers = options.correct_hidden = !naive;
  const part::NozzleClock clock(*twin.scan.log, "twin");
  part::SpeedAndArea speeds;
  ContourFigures f;
  std::vector<std::size_t> layer_rows(64, 0);
  part::MeasurePart(stream, *twin.scan.part, twin.rig, options, [&](const part::PartGeometryRow& g) {
    const bool first = layer_rows[g.layer]++ < part::LayerGrooves::kPoolProfiles;
    const part::PartFlowRow r = part::FlowOf(g, clock, options.correct_hidden);
    if (!r.valid) return;
    speeds.Add(r);
    const sim::PartTruthRow& t = twin.truth[g.profile];
    const double area = std::isnan(r.area_corrected_mm2) ? r.area_mm2 : r.area_corrected_mm2;
    f.laid += t.area_mm2, f.measured += area;
    f.area_rel.push_back(area / t.area_mm2 - 1.0);
    if (first && g.layer > 0) f.first_rel.push_back(f.area_rel.back());
    f.height_error.push_back(g.bead.height_mm - t.height_mm);
    f.flow.push_back(r.flow_mm3_s);
    f.true_flow.push_back(t.area_mm2 * r.head_speed_mm_s);  // the extruder's flow there
  });
  f.bulge = speeds.Bulge();
  return f;
}

using test::MedianAbs;

// The q-quantile of |v|.
double QuantileAbs(std::vector<double> v, double q) {
  for (double& x : v) x = std::abs(x);
  if (v.empty()) return NAN;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

// 100 (1 - |y - yhat| / |y - mean y|): the fit.
double FitPercent(const std::vector<double>& y, const std::vector<double>& yhat) {
  double mean = 0.0;
  for (double v : y) mean += v / static_cast<double>(y.size());
  double err = 0.0, spread = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i)
    err += (y[i] - yhat[i]) * (y[i] - yhat[i]), spread += (y[i] - mean) * (y[i] - mean);
  return 100.0 * (1.0 - std::sqrt(err / spread));
}

// Each corrected row's layer and its error over its sigma (the corrected
// area's), the default options.
struct RowZ {
  int64_t layer;
  double z;
};
std::vector<RowZ> CorrectedZ(const sim::PartTwin& twin) {
  ProfileStream stream("twin", twin.scan.profiles);
  std::vector<RowZ> rows;
  part::MeasurePart(stream, *twin.scan.part, twin.rig, {}, [&](const part::PartGeometryRow& g) {
    if (!g.bead.valid() || std::isnan(g.area_corrected_mm2)) return;
    rows.push_back({g.layer, (g.area_corrected_mm2 - twin.truth[g.profile].area_mm2) / g.area_corrected_sigma_mm2});
  });
  return rows;
}

TEST(PartContour, TheMaterialTheHeightAndTheFlowAlongACornersPath) {
  for (uint64_t seed : {11u, 12u}) {
    sim::PartTwinConfig c;
    c.shape = sim::PartTwinConfig::Shape::kContour;
    c.seed = seed;
    c.area_wave_mm2 = 1.0;
    const sim::PartTwin twin = sim::SimulatePartWall(c);
    const ContourFigures f = Figures(twin, false), naive = Figures(twin, true);
    std::printf(
        "contour seed %llu: area over the run %+.2f %% (naive %+.2f %%), per profile median |error| %.2f %% (naive "
        "%.2f %%), height median |error| %.4f mm (naive %.4f), flow fit %.1f %% (naive %.1f %%); slow %zu profiles: "
        "area %+.1f %%, flow %+.1f %%; each layer's first %zu rows' 90th percentile of |error| %.2f %%\n",
        static_cast<unsigned long long>(seed), 100 * (f.measured / f.laid - 1), 100 * (naive.measured / naive.laid - 1),
        100 * MedianAbs(f.area_rel), 100 * MedianAbs(naive.area_rel), MedianAbs(f.height_error),
        MedianAbs(naive.height_error), FitPercent(f.true_flow, f.flow), FitPercent(naive.true_flow, naive.flow),
        f.bulge.slow, 100 * f.bulge.area_excess, 100 * f.bulge.flow_excess, part::LayerGrooves::kPoolProfiles,
        100 * QuantileAbs(f.first_rel, 0.9));
    EXPECT_LT(std::abs(f.measured / f.laid - 1), 0.01) << seed;
    EXPECT_LT(MedianAbs(f.area_rel), 0.03) << seed;
    EXPECT_LT(MedianAbs(f.height_error), 0.05) << seed;
    EXPECT_GE(FitPercent(f.true_flow, f.flow), 85.0) << seed;
    // Each layer's first rows, measured before its groove shape is pooled,
    // are corrected with it once it is (part/layer_grooves.h): their own
    // free fits put one in ten of them 4.5 % or more off on seed 12.
    EXPECT_LT(QuantileAbs(f.first_rel, 0.9), 0.03) << seed;
    // What the sensor sees counts the grooves: the naive figure is far off.
    EXPECT_GT(naive.measured / naive.laid - 1, 0.05) << seed;
    // The corner bulge: where the head slowed, more area, the same flow
    // (the twin's extruder ignores the head: its wave is +-1/12 of the flow).
    EXPECT_GT(f.bulge.slow, 0u);
    EXPECT_GT(f.bulge.area_excess, 0.2) << seed;
    EXPECT_LT(std::abs(f.bulge.flow_excess), 1.0 / 12.0) << seed;
  }
}

// Passes laid millimetres apart (1.5 mm sigma; seed 21 puts layer 5 3.9 mm
// off layer 4): the beads hang half their width off the one below, and
// through each corner's exit the bead narrows by a fifth in 8 mm of path.
// Each row's interval is the corrected area's +-1.96 sigma: a row beyond
// five of its sigmas has a chance under 1e-6 if the sigma holds what the
// model leaves. Over other walls one row in a thousand or two lies there
// (a mixed point at a wall); a fit carried from the row before past the
// corner's exit put 36 rows of this contour there (up to 13 sigmas, the
// bead 0.6 mm too wide, its top 0.3-0.5 mm off the points).
TEST(PartContour, ABeadHangingHalfOffTheOneBelowIsFittedRowByRowThroughACornersExit) {
  sim::PartTwinConfig c;
  c.shape = sim::PartTwinConfig::Shape::kContour;
  c.seed = 21;
  c.area_wave_mm2 = 1.0;
  c.pass_shift_sigma_mm = 1.5;
  const sim::PartTwin twin = sim::SimulatePartWall(c);
  const std::vector<RowZ> rows = CorrectedZ(twin);
  const std::size_t corrected = rows.size();
  std::size_t covered = 0, beyond_five = 0;
  double worst = 0.0;
  for (const RowZ& r : rows) {
    const double z = std::abs(r.z);
    covered += z <= 1.96, beyond_five += z > 5.0, worst = std::max(worst, z);
  }
  std::printf(
      "half off the one below: %zu rows corrected of %zu, %.1f %% within 1.96 sigma, %zu beyond 5 (worst %.1f)\n",
      corrected, twin.truth.size(), 100.0 * static_cast<double>(covered) / static_cast<double>(corrected), beyond_five,
      worst);
  EXPECT_GT(corrected, 9 * twin.truth.size() / 10);
  EXPECT_LE(beyond_five, corrected / 1000);
  // 95 % less three binomial sigmas of the rows' count.
  const double n = static_cast<double>(corrected);
  EXPECT_GE(static_cast<double>(covered) / n, 0.95 - 3.0 * std::sqrt(0.05 * 0.95 / n));
}

// Boxier beads (exponent 2.6) wandering 1 mm (sigma) off the head's line
// (seed 55): layer 1 lies 3.9 mm off layer 0, on the bed beside it and on
// its shoulder, the surface below rising 2.4 mm under each bead, and its
// registration is 0.022 mm off (1.5 of its sigmas, shared by the layer's
// rows). Moved by the shift, the area seen changes by that rise times it:
// each row's sigma counts it, with the groove's own change (they partly
// cancel). Counted for the groove alone, 105 of layer 1's rows lay beyond
// five sigmas and their errors over their sigmas had an RMS of 3.7.
TEST(PartContour, ABeadBesideTheOneBelowCountsTheShiftsErrorInItsAreaSeen) {
  sim::PartTwinConfig c;
  c.shape = sim::PartTwinConfig::Shape::kContour;
  c.seed = 55;
  c.wander_sigma_mm = 1.0;
  c.exponent = 2.6;
  const sim::PartTwin twin = sim::SimulatePartWall(c);
  const std::vector<RowZ> all = CorrectedZ(twin);
  const std::size_t corrected = all.size();
  std::vector<double> z2(c.layers, 0.0);
  std::vector<std::size_t> rows(c.layers, 0);
  std::size_t beyond_five = 0;
  for (const RowZ& r : all) z2[r.layer] += r.z * r.z, ++rows[r.layer], beyond_five += std::abs(r.z) > 5.0;
  std::printf("beside the one below: %zu rows corrected, %zu beyond 5 sigmas; RMS z by layer:", corrected, beyond_five);
  for (int l = 0; l < c.layers; ++l) std::printf(" %.2f", std::sqrt(z2[l] / static_cast<double>(rows[l])));
  std::printf("\n");
  EXPECT_GT(corrected, 9 * twin.truth.size() / 10);
  // One in 500 (a mixed point at a wall: 1-2 in 1000 on other walls).
  EXPECT_LE(beyond_five, corrected / 500);
  // A layer's rows share its registration's error: a shared error of 1.5
  // sigmas leaves an RMS near 2 even where each sigma holds it.
  for (int l = 0; l < c.layers; ++l) EXPECT_LT(std::sqrt(z2[l] / static_cast<double>(rows[l])), 2.5) << l;
}

}  // namespace
}  // namespace bead
