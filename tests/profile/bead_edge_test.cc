// The bead's edges at coarse sampling (128 points over 50 mm: a spacing d
// of 0.39 mm, a 3 mm bead in eight samples). Each shape is measured at 32
// sampling phases, the bead moved by d/32 at a time: what a run does as
// the bead wanders across the sensor's fixed grid.
//  - a straight sloped wall is located exactly between two samples (the
//    line through the first bead samples meets the surface there);
//  - a parabola (a bead without undercut) is exact at every phase: the
//    parabola through the first three bead samples is its own, and the
//    end-corrected trapezoids are exact for a quadratic;
//  - a vertical wall (undercut seen from above) lies anywhere between two
//    samples: no local model knows where; its area is right on average
//    over phases and each edge within d / 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/profile_processor.h"
#include "libbead/sim/bead_shapes.h"
#include "libbead/sim/sensor_model.h"
#include "tests/support/synthetic.h"

namespace bead {
namespace {

constexpr int kPoints = 128;
constexpr int kPhases = 32;

struct PhaseErrors {
  std::vector<double> area, width;  // measured - exact, one per phase
  double d = 0.0;
  double MeanArea() const { return Mean(area); }
  double MeanWidth() const { return Mean(width); }
  static double Mean(const std::vector<double>& v) {
    double sum = 0.0;
    for (double e : v) sum += e;
    return sum / static_cast<double>(v.size());
  }
  static double MaxAbs(const std::vector<double>& v) {
    double m = 0.0;
    for (double e : v) m = std::max(m, std::abs(e));
    return m;
  }
};

// `make(center)` gives the outline centred there; exact area and width.
template <class Make>
PhaseErrors OverPhases(Make make, double area, double width) {
  PhaseErrors out;
  const auto grid = test::UniformGrid(kPoints);
  out.d = (grid.back() - grid.front()) / (kPoints - 1.0);
  for (int k = 0; k < kPhases; ++k) {
    const double center = 0.1 + out.d * k / kPhases;
    const auto p = test::Render(make(center), {}, grid);
    const BeadGeometry g = MeasureProfile(p.view(), test::kLeft, test::kRight);
    EXPECT_TRUE(g.valid()) << "phase " << k << ": " << StatusName(g.status);
    if (!g.valid()) continue;
    out.area.push_back(g.area_mm2 - area);
    out.width.push_back(g.width_mm - width);
  }
  return out;
}

// Float coordinates of about 25 mm carry 2e-6 mm; the heights and slopes
// built from them a few times that.
constexpr double kRound = 1e-4;

TEST(BeadEdges, SlopedWallsAreLocatedBetweenSamples) {
  // Bottom 6 mm, top 2 mm, height 2 mm: walls of slope 1 over 2 mm, five
  // samples each, so the first three bead samples lie on the wall.
  const PhaseErrors e = OverPhases([](double c) { return sim::TrapezoidOutline(6.0, 2.0, 2.0, c); }, 8.0, 6.0);
  EXPECT_LE(PhaseErrors::MaxAbs(e.width), kRound) << "spacing " << e.d;
  // The corners at the top are kinks the trapezoids cut (by up to
  // slope d^2 / 8 each, -slope d^2 / 12 on average, which the end term
  // restores): exact in the mean over phases, to the phase grid's
  // resolution.
  EXPECT_LE(std::abs(e.MeanArea()), 2 * e.d * e.d / 8.0 / kPhases);
  EXPECT_LE(PhaseErrors::MaxAbs(e.area), 2 * (e.d * e.d / 8.0 + e.d * e.d / 12.0) + kRound);
}

TEST(BeadEdges, ParabolaIsExactAtEveryPhase) {
  const double W = 4.0, H = 2.0;  // a bead without undercut, aspect 2
  const double exact = 2.0 * W * H / 3.0;
  const PhaseErrors e = OverPhases([&](double c) { return sim::ParabolaOutline(W, H, c); }, exact, W);
  // The plain trapezoid integral of the same samples, bare point to bare
  // point (the first round's area): each phase errs by the foot's straight
  // chord (up to slope d^2 / 8 a side, slope 4 H / W = 2 here) less the
  // curved top's chords (slope d^2 / 6), 0.02 mm^2 RMS.
  double plain = 0.0;
  const auto grid = test::UniformGrid(kPoints);
  for (int k = 0; k < kPhases; ++k) {
    const auto p = test::Render(sim::ParabolaOutline(W, H, 0.1 + e.d * k / kPhases), {}, grid);
    double area = 0.0;
    for (std::size_t i = 0; i + 1 < p.x.size(); ++i) area += 0.5 * (p.z[i] + p.z[i + 1]) * (p.x[i + 1] - p.x[i]);
    plain = std::max(plain, std::abs(area - exact));
  }
  // The model's parabola through the first three bead samples is the bead's
  // own, and the end-corrected trapezoids are exact for a quadratic: what
  // is left is the outline's polygon (2001 vertices: chords within
  // |h''| (W / 2000)^2 / 8 of the parabola, |h''| = 8 H / W^2) and float.
  const double sag = 8.0 * H / (W * W) * std::pow(W / 2000.0, 2) / 8.0;
  EXPECT_LE(PhaseErrors::MaxAbs(e.area), sag * W + kRound) << "plain integral's worst " << plain;
  EXPECT_GT(plain, 100.0 * (sag * W + kRound));  // what the model removes
  EXPECT_LE(PhaseErrors::MaxAbs(e.width), 2.0 * sag / (4.0 * H / W) + kRound);
}

TEST(BeadEdges, VerticalWallsAreRightOnAverage) {
  const PhaseErrors e = OverPhases([](double c) { return sim::RectangleOutline(5.0, 2.0, c); }, 10.0, 5.0);
  // Each wall anywhere within a spacing: the area errs by up to H d / 2 a
  // side, the width by up to d / 2 a side; on average over phases by the
  // phase grid's resolution only.
  EXPECT_LE(PhaseErrors::MaxAbs(e.area), 2.0 * 2.0 * e.d / 2.0 + kRound);
  EXPECT_LE(PhaseErrors::MaxAbs(e.width), e.d + kRound);
  EXPECT_LE(std::abs(e.MeanArea()), 2.0 * 2.0 * e.d / 2.0 / kPhases);
  EXPECT_LE(std::abs(e.MeanWidth()), e.d / kPhases);
}

// The twin's bead families (rounded corners, undercut, no undercut), as
// the sensor sees them straight above: unbiased over phases, to the
// scatter of the phases' mean (their standard deviation / sqrt(phases),
// three of it).
TEST(BeadEdges, TwinFamiliesAreUnbiasedOverPhases) {
  using Shape = sim::BeadConfig::Shape;
  for (Shape shape : {Shape::kRoundedRectangle, Shape::kSuperellipse, Shape::kParabola}) {
    sim::BeadConfig config;
    config.shape = shape;
    config.outline_vertices = 400;
    const sim::Outline unit = sim::UnitBeadOutline(config);
    const double unit_area = sim::OutlineArea(unit), area = 6.0;
    const sim::Outline seen0 = sim::ScaledOutline(unit, unit_area, area, 0.0);
    const double visible = sim::VisibleArea(seen0, {}, std::nullopt);
    const PhaseErrors e = OverPhases([&](double c) { return sim::ScaledOutline(unit, unit_area, area, c); }, visible,
                                     sim::OutlineDims(seen0).max_width_mm);
    double var = 0.0;
    const double mean = e.MeanArea();
    for (double a : e.area) var += (a - mean) * (a - mean);
    const double sd = std::sqrt(var / (e.area.size() - 1.0));
    EXPECT_LE(std::abs(mean), 3.0 * sd / std::sqrt(double(e.area.size())) + kRound) << static_cast<int>(shape);
    EXPECT_LE(std::abs(e.MeanWidth()), e.d / 4.0) << static_cast<int>(shape);
  }
}

}  // namespace
}  // namespace bead
