// A wall's bead placed at its silhouette (part/silhouette.h): the ends where
// the seen profile's walls are, the height solved over the top.
#include "libbead/part/silhouette.h"
#include "libbead/part/hidden_groove.h"
#include "libbead/part/silhouette_top.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace bead::part {
namespace {

constexpr double kSpacing = 0.05;  // a profiler's point spacing, mm

// What a sensor looking down sees of `e` over a surface below z = old(x):
// the ellipse's top where it stands over the surface, the surface elsewhere,
// at points `spacing` apart from x = -6 + offset, noise-free.
template <class Old>
Window Seen(const Ellipse& e, Old old, double offset, double spacing = kSpacing) {
  Window w;
  for (double x = -6.0 + offset; x <= 6.0; x += spacing) {
    const double u = (x - e.x0) / e.a, below = old(x);
    const double top = std::abs(u) < 1.0 ? e.z0 + e.Half(x) : -INFINITY;
    w.x.push_back(x), w.old.push_back(below), w.z.push_back(std::max(top, below));
  }
  return w;
}

const SilhouetteScale kScale{0.03, 0.15};
// The layer's shape held: an ellipse of aspect 1/2, known exactly.
const PooledShape kHalf{0.5, 0.0, 2.0, 0.0};
const auto kFlat = [](double) { return 0.0; };

// Each end lies in the cell found for it, whatever the points' phase
// against it (the width no whole number of cells: each end its own);
// with the aspect held, the height is then the truth's to within what an
// end half a cell off moves it.
TEST(Silhouette, TheEndsLieInTheirCellsAndTheHeightFollows) {
  const Ellipse truth{0.13, 0.4, 3.017, 1.5085};
  for (double offset : {0.0, 0.011, 0.023, 0.037, 0.049}) {
    const Window w = Seen(truth, kFlat, offset);
    const auto s = AtSilhouette(w, truth.x0, kScale, &kHalf);
    ASSERT_TRUE(s) << offset;
    EXPECT_LE(s->cell[0], truth.x0 - truth.a) << offset;
    EXPECT_GE(s->cell[1], truth.x0 - truth.a) << offset;
    EXPECT_LE(s->cell[2], truth.x0 + truth.a) << offset;
    EXPECT_GE(s->cell[3], truth.x0 + truth.a) << offset;
    // Each end within half a cell: a within half a cell, b = a / 2 within a
    // quarter, and z0, the mean of the top less b s, within about as much.
    EXPECT_NEAR(s->e.a, truth.a, 0.5 * kSpacing) << offset;
    EXPECT_NEAR(s->e.z0, truth.z0, 0.25 * kSpacing) << offset;
    // The seen walls: z0 over the flat surface, no cliff under either.
    EXPECT_NEAR(s->wall_left, s->e.z0, 1e-12);
    EXPECT_NEAR(s->wall_right, s->e.z0, 1e-12);
    EXPECT_FALSE(s->over_cliff[0] || s->over_cliff[1]) << offset;
  }
}

// With b solved too, noise-free, the aspect is the truth's to the share an
// end half a cell off can move it (its sampling, not its fit): a off by
// half a cell over a, b by about as much the other way.
TEST(Silhouette, TheAspectFreeIsTheTruthsToWithinItsEndsCells) {
  const Ellipse truth{-0.2, 0.3, 3.017, 1.5085};
  const double share = 0.5 * kSpacing / truth.a;
  for (double offset : {0.0, 0.017, 0.033}) {
    const auto s = AtSilhouette(Seen(truth, kFlat, offset), truth.x0, kScale, nullptr);
    ASSERT_TRUE(s) << offset;
    EXPECT_NEAR(s->aspect, 0.5, 0.5 * 2.0 * share) << offset;
    EXPECT_NEAR(s->exponent, 2.0, 2.0 * 2.0 * share) << offset;
    EXPECT_GT(s->residual_variance, 0.0);
    EXPECT_LT(std::sqrt(s->residual_variance), 0.02);  // the top from ends a fraction of a cell off
  }
}

// A tamped bead (a stadium with half-circle ends, c = b / a: part/
// superellipse.h) free is solved as the stadium, not as a superellipse,
// its corner share and aspect the truth's to within its ends' cells (as
// the ellipse's above), over a surface below that is a stadium too.
TEST(Silhouette, ATampedBeadFreeIsTheStadium) {
  const Ellipse truth{0.13, 1.0, 3.2, 1.0, -1.0 / 3.2};
  const Ellipse under{0.43, -1.0, 3.2, 1.0, -1.0 / 3.2};
  const auto old = [&](double x) { return std::abs(x - under.x0) < under.a ? under.z0 + under.Half(x) : -2.0; };
  const double share = 0.5 * kSpacing / truth.a;
  for (double offset : {0.0, 0.011, 0.023, 0.037}) {
    const auto s = AtSilhouette(Seen(truth, old, offset), truth.x0, kScale, nullptr);
    ASSERT_TRUE(s) << offset;
    EXPECT_TRUE(IsStadium(s->exponent)) << offset;
    EXPECT_NEAR(s->aspect, truth.b / truth.a, 2.0 * share * truth.b / truth.a) << offset;
    EXPECT_NEAR(-s->exponent, truth.b / truth.a, 2.0 * share) << offset;
  }
}

// A tamped bead's pool held at a row's width (PooledShape::AtWidth): its
// half-height is held as the tamper holds it, wherever the ends are
// placed and whatever width the row measured. A bead 6.4 mm wide standing
// on a flat bed, its width measured true and 0.8 mm wide (gains past an
// end: a cliff read at another pass's points): b is the pool's 1.0 mm in
// both, and the bead's flat bottom stands on the bed (held as the aspect at
// the width measured, b came out 3.2 / 3.6 of it, 0.89 mm, and the bottom
// 0.22 mm over the bed: a floating outline, the row left uncorrected).
TEST(Silhouette, ATampedBeadHeldKeepsItsHalfHeightWhateverTheWidthMeasured) {
  const Ellipse truth{0.13, 1.0, 3.2, 1.0, -1.0 / 3.2};  // ends' arcs 1 mm wide
  PooledShape pool{truth.b / truth.a, 0.0, truth.p, 0.0};
  pool.exponent_solved = true, pool.half_height_mm = truth.b, pool.corner_mm = 1.0;
  ASSERT_TRUE(pool.Tamped());
  for (const double width : {2.0 * truth.a, 2.0 * truth.a + 0.8}) {
    const PooledShape held = pool.AtWidth(width);
    const auto s = AtSilhouette(Seen(truth, kFlat, 0.0123), truth.x0, kScale, &held);
    ASSERT_TRUE(s) << width;
    EXPECT_NEAR(s->e.b, truth.b, 1e-12) << width;
    // The bottom on the bed to what the ends' cells and the corner's share
    // held at the width measured leave of the top's height (a hundredth of
    // the bead's).
    EXPECT_NEAR(s->e.z0 - s->e.b, 0.0, 0.01 * 2.0 * truth.b) << width;
  }
}

// The same tamped bead seen with 30 um of noise (1.5 % of its height): its
// walls, 1 mm high, show at both ends in every draw, but its top's points
// between them pin its shape poorly (the arcs' few points trade the corner
// share against the half-height: one draw solved b = 3.1 mm for 1.0, its
// widest point a mm under the walls' tops). Either the free shape stands
// over its walls and is placed, or the walls are told as shown but
// unsolved; never neither. (On a generator's tamped wall at this noise,
// 388 of a layer's first 400 rows were so; it was said as "too few of its
// beads overhang to show their walls".) Noise-free, none is.
TEST(Silhouette, WallsShownThatTheTopCannotSolveAreToldApart) {
  const Ellipse truth{0.13, 1.0, 3.2, 1.0, -1.0 / 3.2};
  const Ellipse under{0.43, -1.0, 3.2, 1.0, -1.0 / 3.2};
  const auto old = [&](double x) { return std::abs(x - under.x0) < under.a ? under.z0 + under.Half(x) : -2.0; };
  constexpr double kNoise = 0.03;
  // As part/hidden_groove.cc scales it: max(3 noises, 2 % of the height 2),
  // max(6 noises, 15 % of it).
  const SilhouetteScale scale{3.0 * kNoise, 0.15 * 2.0};
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, kNoise);
  int unsolved = 0;
  std::vector<double> aspects;
  constexpr int kDraws = 20;
  for (int k = 0; k < kDraws; ++k) {
    Window w = Seen(truth, old, 0.011 * k);
    for (double& z : w.z) z += noise(rng);
    FreeSolve free;
    const auto s = AtSilhouette(w, truth.x0, scale, nullptr, nullptr, &free);
    EXPECT_NE(s.has_value(), free.walls_unsolved) << k;
    unsolved += free.walls_unsolved;
    // The stadium alone (a layer whose rows' evidence favours it,
    // part/layer_grooves.h): one shape parameter fewer, its top pins it.
    FreeSolve stadium{true};
    const auto t = AtSilhouette(w, truth.x0, scale, nullptr, nullptr, &stadium);
    if (!t) continue;
    EXPECT_TRUE(IsStadium(t->exponent)) << k;
    aspects.push_back(t->aspect);
  }
  EXPECT_GT(unsolved, kDraws / 2);
  // Each row's aspect scatters (about a fifth of it, the noise on its few
  // arc points); their mean is the bead's within three standard errors.
  ASSERT_GT(aspects.size(), kDraws - kDraws / 4);
  const double n = aspects.size(), mean = std::accumulate(aspects.begin(), aspects.end(), 0.0) / n;
  double var = 0.0;
  for (double a : aspects) var += (a - mean) * (a - mean) / (n - 1.0);
  EXPECT_NEAR(mean, truth.b / truth.a, 3.0 * std::sqrt(var / n));
  FreeSolve free;
  EXPECT_TRUE(AtSilhouette(Seen(truth, old, 0.0), truth.x0, scale, nullptr, nullptr, &free));
  EXPECT_FALSE(free.walls_unsolved);
}

// Past a bead's right end the wall of the layers below drops to the bed; read
// at another pass's points, that cliff leaves gains of 0.7 and 1.2 mm beyond
// the bead (as a generator's pressed wall seen at points 0.2 mm apart did),
// and the largest rise lies there, two points out, its step over the cliff
// (the surface below falls 5 mm across it). The next rise is the bead's
// own wall: taken there, the end lies within a spacing of the truth's and
// the top fits to the spacing's share.
TEST(Silhouette, ARiseOverACliffPastTheEndIsToldAndTheNextIsTheWall) {
  constexpr double kCoarse = 0.2;
  const Ellipse truth{-0.1, 10.2, 3.15, 1.575};
  Window w;
  for (int k = 0; k <= 60; ++k) {
    const double x = -6.0 + kCoarse * k;
    // The surface below falling past the bead's end, and the gains read there.
    // (On the left the bead overhangs a drop to a lower layer.)
    const double old = k < 14    ? 1.3
                       : k == 14 ? 5.2
                       : k < 45  ? 9.0
                       : k == 45 ? 9.05
                       : k == 46 ? 8.1
                       : k == 47 ? 4.3
                                 : 0.0;
    const double spurious = k == 46 ? 0.7 : k == 47 ? 1.2 : 0.0;
    const double top = std::abs(x - truth.x0) < truth.a ? truth.z0 + truth.Half(x) : -INFINITY;
    w.x.push_back(x), w.old.push_back(old), w.z.push_back(std::max(top, old + spurious));
  }
  const auto largest = AtSilhouette(w, truth.x0, kScale, nullptr);
  ASSERT_TRUE(largest);
  EXPECT_GT(largest->e.x0 + largest->e.a, truth.x0 + truth.a + kCoarse);  // placed two points out
  EXPECT_TRUE(largest->over_cliff[1]);
  EXPECT_FALSE(largest->over_cliff[0]);
  SilhouetteScale next = kScale;
  next.wall_rank[1] = 1;
  const auto wall = AtSilhouette(w, truth.x0, next, nullptr);
  ASSERT_TRUE(wall);
  EXPECT_NEAR(wall->e.x0 + wall->e.a, truth.x0 + truth.a, kCoarse);
  EXPECT_LT(std::sqrt(wall->residual_variance), std::sqrt(largest->residual_variance) / 3.0);
  EXPECT_LT(std::sqrt(wall->residual_variance), TopSamplingMm(0.5, kCoarse) + 0.01);
  // The area the run counted between the two walls is not the bead's: the
  // gains' trapezoids from the point past its wall to the cliff's foot.
  const double between = 0.5 * (0.7 + 1.2) * kCoarse + 0.5 * 1.2 * kCoarse;
  EXPECT_NEAR(wall->seen_adjust, -between, 1e-9);
}

// A bead sunk so deep that its sides meet the surface below shows no wall:
// nothing to place it by (the fit's work, not the silhouette's), and no
// wall is told as shown.
TEST(Silhouette, ABeadWhoseSidesMeetTheSurfaceBelowHasNone) {
  const Ellipse sunk{0.0, -0.6, 3.0, 1.5};
  FreeSolve free;
  EXPECT_FALSE(AtSilhouette(Seen(sunk, kFlat, 0.0), 0.0, kScale, nullptr, nullptr, &free));
  EXPECT_FALSE(free.walls_unsolved);
  EXPECT_FALSE(AtSilhouette(Seen(sunk, kFlat, 0.0), 0.0, kScale, &kHalf));
  // Nor does a profile with nothing over the surface at the centre.
  EXPECT_FALSE(AtSilhouette(Seen(sunk, kFlat, 0.0), 5.5, kScale, &kHalf));
  // Seen at points 0.2 mm apart, a bead whose widest point lies on the
  // surface (a half ellipse laid on it) rises from one point to the next as
  // steeply as a wall; placed there, it stands on the surface by no wall.
  const Ellipse on{0.0, 0.0, 1.5, 0.8};
  for (double offset : {0.03, 0.09, 0.15})
    EXPECT_FALSE(AtSilhouette(Seen(on, kFlat, offset, 0.2), 0.0, kScale, nullptr)) << offset;
}

// On the layer below's shoulder (a surface rising toward the bead), the
// walls are z0 less the surface there, each side its own.
TEST(Silhouette, TheWallsStandOnTheSurfaceBelowWhereTheEndsAre) {
  const Ellipse truth{0.4, 1.2, 3.0, 1.5};
  const auto hill = [](double x) { return 1.0 - 0.04 * x * x; };  // an old bead's top under the new one
  const auto s = AtSilhouette(Seen(truth, hill, 0.0), truth.x0, kScale, &kHalf);
  ASSERT_TRUE(s);
  const double L = s->e.x0 - s->e.a, R = s->e.x0 + s->e.a;
  EXPECT_NEAR(s->wall_left, s->e.z0 - hill(L), 1e-3);
  EXPECT_NEAR(s->wall_right, s->e.z0 - hill(R), 1e-3);
  // The bead's centre right of the old one's top: its right end farther
  // down the shoulder, over a lower surface.
  EXPECT_GT(s->wall_right, s->wall_left);
}

// The groove of e over a flat surface at 0: its lower outline's shadow
// above 0, finely summed (the void under the overhang that the area seen
// counts as material).
double FlatGroove(const Ellipse& e) {
  double sum = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double x = e.x0 + e.a * (-1.0 + (k + 0.5) * 2.0 / n);
    sum += std::max(0.0, e.z0 - e.Half(x)) * e.a * 2.0 / n;
  }
  return sum;
}

// Its material above 0: the ellipse there.
double FlatMaterial(const Ellipse& e) {
  double sum = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double h = e.Half(e.x0 + e.a * (-1.0 + (k + 0.5) * 2.0 / n));
    sum += std::max(0.0, e.z0 + h - std::max(e.z0 - h, 0.0)) * e.a * 2.0 / n;
  }
  return sum;
}

// FlatGroove's gradient in x0, z0, a and b, by central differences.
void FlatGradient(const Ellipse& e, double gradient[4]) {
  for (std::size_t i = 0; i < 4; ++i) {
    Ellipse up = e, down = e;
    up[i] += 1e-5, down[i] -= 1e-5;
    gradient[i] = (FlatGroove(up) - FlatGroove(down)) / 2e-5;
  }
}

// Where the ends lie in their cells is what the placement cannot see:
// over the points' phases against beads of widths a fraction of a cell
// apart (each end's place in its cell its own; noise-free), the area seen
// (the trapezoids of the gain, as part/added_bead.h sums it) less the
// groove of the ellipse placed misses the material by as much as the
// variance's ends say: its RMS within a factor of two of their predicted
// sigma, its mean within two of them.
TEST(Silhouette, TheEndsVarianceIsWhatTheirPlacesInTheCellsMove) {
  double sum = 0.0, sum2 = 0.0, predicted = 0.0;
  int runs = 0;
  for (int m = 0; m < 5; ++m) {
    const Ellipse truth{0.13, 0.4, 3.003 + 0.0093 * m, 0.5 * (3.003 + 0.0093 * m)};
    const double material = FlatMaterial(truth);
    for (int k = 0; k < 8; ++k, ++runs) {
      const Window w = Seen(truth, kFlat, kSpacing * k / 8.0);
      auto s = AtSilhouette(w, truth.x0, kScale, &kHalf);
      ASSERT_TRUE(s) << m << " " << k;
      double seen = 0.0;
      for (std::size_t j = 0; j + 1 < w.x.size(); ++j)
        seen += 0.5 * (std::max(w.Gain(j), 0.0) + std::max(w.Gain(j + 1), 0.0)) * (w.x[j + 1] - w.x[j]);
      const double error = seen + s->seen_adjust - FlatGroove(s->e) - material;
      sum += error, sum2 += error * error;
      double gradient[4];
      FlatGradient(s->e, gradient);
      s->residual_variance = 0.0;  // noise-free: the ends alone
      predicted += SilhouetteVariance(*s, &kHalf, gradient, 0.0);
    }
  }
  const double rms = std::sqrt(sum2 / runs), sigma = std::sqrt(predicted / runs);
  std::printf("over %d beads: error mean %+.4f, RMS %.4f mm^2; the ends' sigma %.4f mm^2\n", runs, sum / runs, rms,
              sigma);
  EXPECT_GT(rms, 0.5 * sigma);
  EXPECT_LT(rms, 2.0 * sigma);
  EXPECT_LT(std::abs(sum / runs), 2.0 * sigma);
}

// With the layer's shape held, the top says where in its cell each end
// lies (part/silhouette.cc: PlaceByTop): over the points' phases against a
// noise-free bead whose width is a whole number of cells (both ends at the
// same place in theirs), the ends in the middle quarter of their cells are
// placed within a tenth of a spacing of the truth, those nearer a point
// within a fifth (the top's place drawn toward the middle by the cell's
// uniform, by up to a tenth of the half cell, and the vertex read from the
// three places nearest the edge), and the errors' RMS is under half the
// cells' middles', those in the middle quarter and those nearer a point alike
// (these stayed at the middles before: the top's least lay at the cell's
// first or last place, and the top read over the points within 0.9 of each
// place's half-width drew the least to where a point left it). Each stays
// in its cell. (Where one end lies near a point and the other in its
// cell's middle, the first left at its middle moved the top the second is
// placed by: on a bead 3.017 mm wide, such ends came out up to 0.01 mm off,
// a fifth of a cell.)
TEST(Silhouette, AHeldShapesTopPlacesEachEndInItsCell) {
  const Ellipse truth{0.13, 0.4, 3.0, 1.5};
  double placed2[2] = {0.0, 0.0}, middle2[2] = {0.0, 0.0};
  int ends[2] = {0, 0};
  for (int k = 0; k < 40; ++k) {
    const double offset = kSpacing * k / 40.0;
    const auto s = AtSilhouette(Seen(truth, kFlat, offset), truth.x0, kScale, &kHalf);
    ASSERT_TRUE(s) << offset;
    for (int side = 0; side < 2; ++side) {
      const double lo = s->cell[2 * side], hi = s->cell[2 * side + 1];
      const double end = side ? truth.x0 + truth.a : truth.x0 - truth.a;
      const double placed = side ? s->e.x0 + s->e.a : s->e.x0 - s->e.a;
      EXPECT_GE(placed, lo - 1e-12) << offset;
      EXPECT_LE(placed, hi + 1e-12) << offset;
      const double share = (end - lo) / (hi - lo);
      const int near_a_point = share < 0.375 || share > 0.625;
      EXPECT_NEAR(placed, end, (near_a_point ? 0.2 : 0.1) * kSpacing) << offset << " side " << side;
      placed2[near_a_point] += (placed - end) * (placed - end);
      middle2[near_a_point] += std::pow(0.5 * (lo + hi) - end, 2);
      ++ends[near_a_point];
    }
  }
  for (int near = 0; near < 2; ++near) {
    std::printf("%d ends %s: placed RMS %.4f mm, the middles' %.4f\n", ends[near],
                near ? "nearer a point" : "in their cells' middle quarter", std::sqrt(placed2[near] / ends[near]),
                std::sqrt(middle2[near] / ends[near]));
    EXPECT_GE(ends[near], 16);  // 20 and 60 of 80 ends on average
    EXPECT_LT(placed2[near], 0.25 * middle2[near]);
  }
}

// The area seen, the gain's trapezoids as part/added_bead.h sums them.
double SeenArea(const Window& w) {
  double seen = 0.0;
  for (std::size_t j = 0; j + 1 < w.x.size(); ++j)
    seen += 0.5 * (std::max(w.Gain(j), 0.0) + std::max(w.Gain(j + 1), 0.0)) * (w.x[j + 1] - w.x[j]);
  return seen;
}

// w without its points between `from` and `to` mm of the bead's left and
// right ends (outside the end: positive).
Window Lost(const Window& whole, const Ellipse& e, double from, double to) {
  Window out;
  for (std::size_t j = 0; j < whole.x.size(); ++j) {
    const double left = (e.x0 - e.a) - whole.x[j], right = whole.x[j] - (e.x0 + e.a);
    if ((left > from && left < to) || (right > from && right < to)) continue;
    out.x.push_back(whole.x[j]), out.z.push_back(whole.z[j]), out.old.push_back(whole.old[j]);
  }
  return out;
}

// A profiler that loses the points next to the walls: a triangulation
// camera's view of the surface beside the bead blocked by it (the points
// just outside each end), or a face too steep to return the laser (either
// side). The shape is not solved from such a bead (placed at the gap's
// middle, 0.05 mm out for a 0.1 mm shadow, an independent wall's pool came
// out 0.55-0.59 for an aspect of 0.5, "toward a box", within sigmas of
// 0.002). With the shape held, each end is placed in its gap where the
// top fits best, its cell narrowed to what the fit's curvature says (at
// least a spacing), which holds the true end; and the area seen, less the groove, with what the gap's
// trapezoid counted for the end at the gap's middle given back, is the
// material to within the ends' sigma, over the points' phases, where the
// trapezoid alone is off by a multiple of it.
TEST(Silhouette, PointsLostBesideTheWallsArePlacedByTheTop) {
  const Ellipse truth{0.13, 0.4, 3.017, 1.5085};
  for (const auto& [from, to] : {std::pair{0.0, 0.12}, std::pair{-0.12, 0.12}}) {
    double worst_trapezoid = 0.0;
    for (double offset : {0.0, 0.011, 0.023, 0.037}) {
      const Window whole = Seen(truth, kFlat, offset), lost = Lost(whole, truth, from, to);
      EXPECT_TRUE(AtSilhouette(whole, truth.x0, kScale, nullptr));
      EXPECT_FALSE(AtSilhouette(lost, truth.x0, kScale, nullptr)) << from << " " << offset;
      const auto g = AtSilhouette(lost, truth.x0, kScale, &kHalf);
      ASSERT_TRUE(g) << from << " " << offset;
      for (int side = 0; side < 2; ++side) {
        const double end = side ? truth.x0 + truth.a : truth.x0 - truth.a;
        EXPECT_LE(g->cell[2 * side], end + 1e-9) << from << " " << offset;
        EXPECT_GE(g->cell[2 * side + 1], end - 1e-9) << from << " " << offset;
        // At least a spacing (half of one where the gap's edge clips it),
        // as wide as the top's fit places it, and narrower than the gap (a
        // spacing wider than what was lost).
        EXPECT_GE(g->cell[2 * side + 1] - g->cell[2 * side], 0.5 * kSpacing - 1e-9);
        EXPECT_LT(g->cell[2 * side + 1] - g->cell[2 * side], (to - from) + 0.5 * kSpacing);
      }
      double gradient[4];
      FlatGradient(g->e, gradient);
      Silhouette g0 = *g;
      g0.residual_variance = 0.0;  // noise-free: the ends alone
      const double sigma = std::sqrt(SilhouetteVariance(g0, &kHalf, gradient, 0.0));
      const double seen = SeenArea(lost), material = FlatMaterial(truth);
      std::printf("lost %.2f..%.2f mm, offset %.3f: corrected %+.4f, trapezoid alone %+.4f mm^2, sigma %.4f\n", from,
                  to, offset, seen + g->seen_adjust - FlatGroove(g->e) - material, seen - FlatGroove(g->e) - material,
                  sigma);
      EXPECT_LT(std::abs(seen + g->seen_adjust - FlatGroove(g->e) - material), 3.0 * sigma) << from << " " << offset;
      worst_trapezoid = std::max(worst_trapezoid, std::abs(seen - FlatGroove(g->e) - material) / sigma);
    }
    if (from == 0.0) {
      EXPECT_GT(worst_trapezoid, 3.0) << "the shadow's trapezoid alone was within the sigma";
    }
  }
}

// A bead laid beside the one below rather than on it (an independent
// generator's wall, wandering 1 mm a layer: the new bead on the bed, its
// centre 2.53 mm off the old one's, its right side against the old bead's
// flank, the old top standing above it there). The old bead's flank makes a
// step inside the run over the floor: taken for the bead's end, the bead
// came out half as wide (a half-width of 1.25 mm for 2.47), its groove
// -41 % at 9 sigmas. Where the walls found span less than the run, there is
// no silhouette (the fit's work).
TEST(Silhouette, AStepInsideTheRunIsNotTheBeadsEnd) {
  const Ellipse below{0.0, 0.9438, 2.5169, 1.2585};
  const auto old = [&](double x) { return std::abs(x - below.x0) < below.a ? below.z0 + below.Half(x) : 0.0; };
  const Ellipse bead{-2.531, 0.9266, 2.471, 1.2355};
  for (double offset : {0.0, 0.013, 0.029, 0.041}) {
    const Window w = Seen(bead, old, offset);
    for (const PooledShape* held : {static_cast<const PooledShape*>(nullptr), &kHalf}) {
      const auto s = AtSilhouette(w, bead.x0, kScale, held);
      if (s) {
        EXPECT_NEAR(s->e.a, bead.a, 2.0 * kSpacing) << offset << (held ? " held" : " free");
      }
    }
  }
}

// A bead of another shape: from near a diamond to near a box, the free
// placement finds its exponent to within what an end half a cell off moves
// it (as the ellipse's aspect above). Its aspect is looser: on a box's flat
// top z0 and b part only by the outer points (p = 3.5: 2.4 % off at one
// phase). Held at what it found (a layer's pool of one), the groove of the
// bead placed, taken off the area seen, leaves the material to within the
// ends' sigma.
TEST(Silhouette, ABeadOfAnotherShapeIsPlacedWithItsExponent) {
  double aspect_err2 = 0.0, aspect_var = 0.0, exponent_err2 = 0.0, exponent_var = 0.0;
  for (double p : {1.5, 2.6, 3.5}) {
    double sum = 0.0, variance = 0.0;
    for (int m = 0; m < 4; ++m) {
      const double offset = 0.013 * m;
      const Ellipse truth{0.13, 0.6, 3.003 + 0.0093 * m, 0.5 * (3.003 + 0.0093 * m), p};
      const double share = 0.5 * kSpacing / truth.a;
      const Window w = Seen(truth, kFlat, offset);
      const auto free = AtSilhouette(w, truth.x0, kScale, nullptr);
      ASSERT_TRUE(free) << p << " " << m;
      EXPECT_NEAR(free->exponent, p, p * 2.0 * share) << m;
      aspect_err2 += (free->aspect - 0.5) * (free->aspect - 0.5),
          aspect_var += free->aspect_end_var + free->aspect_grid_var;
      exponent_err2 += (free->exponent - p) * (free->exponent - p) / (p * p),
          exponent_var += (free->exponent_end_var + free->exponent_grid_var) / (p * p);
      const PooledShape found{free->aspect, 0.0, free->exponent, 0.0};
      auto s = AtSilhouette(w, truth.x0, kScale, &found);
      ASSERT_TRUE(s) << p << " " << m;
      double seen = 0.0;
      for (std::size_t j = 0; j + 1 < w.x.size(); ++j)
        seen += 0.5 * (std::max(w.Gain(j), 0.0) + std::max(w.Gain(j + 1), 0.0)) * (w.x[j + 1] - w.x[j]);
      double gradient[4];
      FlatGradient(s->e, gradient);
      s->residual_variance = 0.0;  // noise-free: the ends alone
      const double error = seen - FlatGroove(s->e) - FlatMaterial(truth);
      const double sigma = std::sqrt(SilhouetteVariance(*s, &found, gradient, 0.0));
      std::printf("p %.2f, a %.4f: exponent %.4f, aspect %.4f; area less groove %+.4f mm^2, the ends' sigma %.4f\n", p,
                  truth.a, free->exponent, free->aspect, error, sigma);
      EXPECT_LT(std::abs(error), 3.0 * sigma) << p << " " << m;
      sum += error, variance += sigma * sigma;
    }
    EXPECT_LT(std::abs(sum / 4.0), 2.0 * std::sqrt(variance / 4.0)) << p;
  }
  // The free shape's ends placed within their cells by the top, what is
  // left of its error over the phases is the placement's convergence (a
  // hundredth of a cell) and the exponent grid's interpolation: under a
  // tenth of what an end half a cell off moves the aspect (share of it) or
  // the exponent (twice that), and within two of the sigma the placement
  // and the grid's next order give it. (Placed at the cells' middles, its
  // RMS was 0.0049, 0.6 of the cells' share.)
  const double share = 0.5 * kSpacing / 3.0;
  const double aspect_rms = std::sqrt(aspect_err2 / 12), aspect_sigma = std::sqrt(aspect_var / 12);
  const double exponent_rms = std::sqrt(exponent_err2 / 12), exponent_sigma = std::sqrt(exponent_var / 12);
  std::printf("aspect: error RMS %.4f, its sigma %.4f; exponent (relative): %.4f, %.4f\n", aspect_rms, aspect_sigma,
              exponent_rms, exponent_sigma);
  EXPECT_LT(aspect_rms, 0.1 * 0.5 * share);
  EXPECT_LT(exponent_rms, 0.1 * 2.0 * share);
  EXPECT_LT(aspect_rms, 2.0 * aspect_sigma);
  EXPECT_LT(exponent_rms, 2.0 * exponent_sigma);
}

// A bead near a box (exponent 7: the grid has no two exponents beyond it)
// keeps its ends at their cells' middles for the pool, each anywhere in its
// cell: its shape still solved, its variance from the ends not nothing.
TEST(Silhouette, ABeadAtTheGridsEndKeepsItsEndsAnywhereInTheirCells) {
  const Ellipse truth{0.13, 0.6, 3.003, 1.5015, 7.0};
  const auto free = AtSilhouette(Seen(truth, kFlat, 0.021), truth.x0, kScale, nullptr);
  ASSERT_TRUE(free);
  EXPECT_NEAR(free->exponent, 7.0, 0.7);  // within the grid's last step
  EXPECT_NEAR(free->aspect, 0.5, 0.5 * 2.0 * 0.5 * kSpacing / truth.a);
  EXPECT_FALSE(std::isfinite(free->end_sigma[0]));
  EXPECT_GT(free->aspect_end_var, 0.0);
}

// No point of a top lies under its widest point: an outermost point more
// than three residual sigmas under z0 is not on the top (a footprint's mix
// of the end and the wall's foot, or the layer below's wall beside the
// end), and its end's cell reaches inward to the first point that is; a
// point within three sigmas under z0 is on it (its noise), and a gapped
// side is left to the gap's placement.
TEST(Silhouette, APointUnderTheTopsWidestPointIsNotOnIt) {
  Window w;
  // A top of z0 = 1 over points 2-12 (x 0.2 to 1.2, 0.1 mm apart), on a
  // surface below at 0 that points 0, 1, 13 and 14 show: the two outermost
  // top points on the left a wall's foot mixed in, the right one 0.02 under z0.
  for (int j = 0; j <= 14; ++j) w.x.push_back(0.1 * j), w.z.push_back(1.2), w.old.push_back(0.0);
  w.z[0] = w.z[1] = w.z[13] = w.z[14] = 0.0;
  w.z[2] = 0.5, w.z[3] = 0.9, w.z[12] = 0.98;
  const bool open[2] = {false, false}, gapped_left[2] = {true, false};
  const auto cells = [] { return std::array<double, 4>{0.1, 0.2, 1.2, 1.3}; };
  auto cell = cells();
  const auto [first, last] = OnTheTop(w, 2, 12, 1.0, 0.01, open, cell.data());
  EXPECT_EQ(first, 4u);
  EXPECT_EQ(last, 12u);
  EXPECT_DOUBLE_EQ(cell[0], 0.1);
  EXPECT_DOUBLE_EQ(cell[1], 0.4);  // reaches the first point on the top
  EXPECT_DOUBLE_EQ(cell[2], 1.2);  // 0.02 under z0: two sigmas, on the top
  EXPECT_DOUBLE_EQ(cell[3], 1.3);
  auto kept = cells();
  EXPECT_EQ(OnTheTop(w, 2, 12, 1.0, 0.01, gapped_left, kept.data()).first, 2u);
  EXPECT_DOUBLE_EQ(kept[1], 0.2);
  // With a sigma of 0.002, the right one is off the top too.
  auto tight = cells();
  EXPECT_EQ(OnTheTop(w, 2, 12, 1.0, 0.002, open, tight.data()).second, 11u);
  EXPECT_DOUBLE_EQ(tight[2], 1.1);
  // A top whose z0 stands over every point (no point on it): nothing said.
  auto none = cells();
  const auto [a, b] = OnTheTop(w, 2, 12, 2.0, 0.01, open, none.data());
  EXPECT_EQ(a, 2u);
  EXPECT_EQ(b, 12u);
  EXPECT_DOUBLE_EQ(none[1], 0.2);
  EXPECT_DOUBLE_EQ(none[2], 1.2);
  // The cell's outer point standing over the surface below (a mix of the
  // foot and an end beyond it): the cell reaches out to the point past it.
  w.z[1] = 0.3;
  auto out = cells();
  OnTheTop(w, 2, 12, 1.0, 0.01, open, out.data());
  EXPECT_DOUBLE_EQ(out[0], 0.0);
  EXPECT_DOUBLE_EQ(out[3], 1.3);
}

// A profiler whose points each average the surface over a spot as wide as
// their spacing mixes an end of the top and the wall's foot: the point
// whose spot holds the end stands between them. Where it is the cell's
// inner point it is under the top's widest point, not on the top; where it
// is the outer one it stands over the surface below, the end possibly
// beyond it (part/silhouette_top.h: OnTheTop). Here the bead overhangs a
// narrower one below by 0.4 mm a side, its wall 2.1 mm deep, at eight
// phases against the points: with the shape held, each end lies in its
// cell at every phase (placed by the largest rise alone, the end lay
// outside it at one phase, beyond a mix). The free shape's aspect, its
// ends placed from the points on the top, is printed: over the phases
// -0.0020 (-0.0031 placed from the mixed points), what is left the spot's
// averaging of the steep top near the end, which the model does not know.
template <class Old>
Window SeenThroughASpot(const Ellipse& e, Old old, double offset) {
  constexpr int kSub = 50;  // the spot's subsamples
  const Window fine = Seen(e, old, offset - 0.5 * kSpacing + 0.5 * kSpacing / kSub, kSpacing / kSub);
  Window w;
  for (std::size_t j = 0; j + kSub <= fine.x.size(); j += kSub) {
    double z = 0.0, old = 0.0;
    for (std::size_t k = j; k < j + kSub; ++k) z += fine.z[k] / kSub, old += fine.old[k] / kSub;
    w.x.push_back(0.5 * (fine.x[j] + fine.x[j + kSub - 1])), w.old.push_back(old), w.z.push_back(z);
  }
  return w;
}

TEST(Silhouette, APointMixingTheEndAndTheWallsFootIsNotOnTheTop) {
  double mean = 0.0;
  const int phases = 8;
  for (int m = 0; m < phases; ++m) {
    const double offset = kSpacing * m / phases;
    const Ellipse truth{0.13, 0.6, 3.003 + 0.0093 * m, 0.5 * (3.003 + 0.0093 * m)};
    const auto below = [&truth](double x) { return std::abs(x - truth.x0) < truth.a - 0.4 ? 0.0 : -1.5; };
    const Window w = SeenThroughASpot(truth, below, offset);
    const auto free = AtSilhouette(w, truth.x0, kScale, nullptr);
    const auto held = AtSilhouette(w, truth.x0, kScale, &kHalf);
    ASSERT_TRUE(free && held) << m;
    EXPECT_LE(held->cell[0], truth.x0 - truth.a) << m;
    EXPECT_GE(held->cell[1], truth.x0 - truth.a) << m;
    EXPECT_LE(held->cell[2], truth.x0 + truth.a) << m;
    EXPECT_GE(held->cell[3], truth.x0 + truth.a) << m;
    mean += (free->aspect - 0.5) / phases;
  }
  std::printf("the free shape's aspect over the phases: %+.4f\n", mean);
}

// Through the same spot, on a flat surface below, with the layer's pool
// saying the profiler averages over a footprint: the area seen across each
// wall's cell is taken as the bead placed shows it (seen_adjust), so its
// error moves with the end's place in the cell as the groove's does, a
// mixed end's too. The area less the groove of the bead held at its shape
// lies within three of its sigmas at every phase, and its errors' RMS over
// the phases within a factor of two of the sigmas'. (Counted as if the
// area seen followed a mixed end, the spots' integral across the cell,
// these rows' sigmas left out the wall times the place: a generator's
// tamped beads on the bed came out at 0.024 mm^2 for sigmas of 0.015.)
TEST(Silhouette, ThroughASpotTheAreaSeenIsThePlacedBeads) {
  PooledShape footprint = kHalf;
  footprint.footprint = true;
  double err2 = 0.0, var = 0.0;
  int mixed = 0;
  const int phases = 8;
  for (int m = 0; m < phases; ++m) {
    const Ellipse truth{0.13, 0.6, 3.003 + 0.0093 * m, 0.5 * (3.003 + 0.0093 * m)};
    const Window w = SeenThroughASpot(truth, kFlat, kSpacing * m / phases);
    auto s = AtSilhouette(w, truth.x0, kScale, &footprint);
    ASSERT_TRUE(s) << m;
    mixed += s->end_mixed[0] + s->end_mixed[1];
    double gradient[4];
    FlatGradient(s->e, gradient);
    s->residual_variance = 0.0;  // noise-free: the ends alone
    const double error = SeenArea(w) + s->seen_adjust - FlatGroove(s->e) - FlatMaterial(truth);
    const double sigma = std::sqrt(SilhouetteVariance(*s, &footprint, gradient, 0.0));
    std::printf("phase %d: area less groove %+.4f mm^2, sigma %.4f\n", m, error, sigma);
    EXPECT_LT(std::abs(error), 3.0 * sigma) << m;
    err2 += error * error, var += sigma * sigma;
  }
  std::printf("RMS: error %.4f, sigma %.4f\n", std::sqrt(err2 / phases), std::sqrt(var / phases));
  EXPECT_GT(mixed, 0);
  EXPECT_LT(std::sqrt(err2 / var), 2.0);
  EXPECT_GT(std::sqrt(err2 / var), 0.5);
}

// What the points' spacing leaves on the top of the right shape
// (part/hidden_groove.h: TopSamplingMm, in the layer's top test beside the
// noise): an ellipse of aspect 1/2 seen at points 0.2 mm apart, noise-free,
// its ends each placed anywhere in a cell a spacing wide, its height and
// size solved over the top (|u| < 0.9) as the free shape's are. The top's
// RMS over 400 placements stays under the bound (the refit takes up part)
// and is most of it: at this spacing it is what a right shape's top
// leaves, 1.4 times a 10 um noise and 0.5 % of a 2 mm height together.
TEST(Silhouette, TheEndsCellsLeaveTheTopWhatTheSamplingBoundSays) {
  constexpr double kA = 3.0, kB = 1.5, kStep = 0.2;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> in_cell(-0.5 * kStep, 0.5 * kStep), phase(0.0, kStep);
  double sum2 = 0.0;
  std::size_t n = 0;
  for (int draw = 0; draw < 400; ++draw) {
    const double off = phase(rng), left = -kA + in_cell(rng), right = kA + in_cell(rng);
    const double x0 = 0.5 * (left + right), a = 0.5 * (right - left);
    // Least squares of z = z0 + b s(u) over the top's points.
    std::vector<double> s_top, z_top;
    for (double x = -5.0 + off; x < 5.0; x += kStep) {
      const double u = (x - x0) / a;
      if (std::abs(u) >= 0.9 || std::abs(x) >= kA) continue;
      s_top.push_back(std::sqrt(1.0 - u * u)), z_top.push_back(kB * std::sqrt(1.0 - (x / kA) * (x / kA)));
    }
    double m = 0, ss = 0, sz = 0, zz = 0, szz = 0;
    for (std::size_t k = 0; k < s_top.size(); ++k)
      m += 1, ss += s_top[k], sz += z_top[k], zz += s_top[k] * s_top[k], szz += s_top[k] * z_top[k];
    const double det = m * zz - ss * ss, b = (m * szz - ss * sz) / det, z0 = (sz - b * ss) / m;
    for (std::size_t k = 0; k < s_top.size(); ++k, ++n) sum2 += std::pow(z_top[k] - z0 - b * s_top[k], 2);
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(n)), bound = TopSamplingMm(kB / kA, kStep);
  EXPECT_LT(rms, bound);
  EXPECT_GT(rms, 0.5 * bound);
  EXPECT_GT(bound, 1.4 * TopTolerance(0.01, 2.0));
}

}  // namespace
}  // namespace bead::part
