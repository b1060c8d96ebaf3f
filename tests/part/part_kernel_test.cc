// The hidden groove's ellipse sums four points a register
// (part/part_kernel.h) against their definition written point by point
// (part/hidden_groove.cc), in both builds, with the aspect fitted and held;
// the held top's sums against the superellipse's table read point by point,
// and the surface below at many places against the grid's;
// the points moved into the bed frame; the bits' NaN and finite tests
// (core/float_bits.h) the loops use.
#include "libbead/part/part_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "libbead/core/float_bits.h"
#include "libbead/core/median.h"
#include "libbead/part/registration.h"
#include "libbead/part/superellipse.h"
#include "libbead/part/surface_below.h"

namespace bead::part {
namespace {

// The definition: the sensor sees the ellipse's top where it stands above
// the surface below; d/dx0 = b u / (a s), d/dz0 = 1, d/da = b u^2 / (a s)
// (+ aspect s held), d/db = s (0 held), s held at 0.02 or more; zero where
// the surface below is seen.
// `size`: each sum's terms' sizes, what its rounding scales with.
EllipseSums PointByPoint(const std::vector<double>& x, const std::vector<double>& z, const std::vector<double>& old,
                         const EllipseAt& e, EllipseSums& size) {
  const bool held = std::isfinite(e.aspect);
  EllipseSums out;
  size = {};
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double u = (x[j] - e.x0) / e.a, s = std::abs(u) < 1.0 ? std::sqrt(1.0 - u * u) : 0.0;
    const double top = e.z0 + e.b * s;
    const bool seen = s > 0.0 && top > old[j];
    const double r = (seen ? top : old[j]) - z[j];
    out.rss += r * r, size.rss += r * r;
    if (!seen) continue;
    const double sd = std::max(s, 0.02);
    const double g[4] = {e.b * u / (e.a * sd), 1.0, e.b * u * u / (e.a * sd) + (held ? e.aspect * s : 0.0),
                         held ? 0.0 : s};
    for (int i = 0, k = 0; i < 4; ++i) {
      for (int m = i; m < 4; ++m, ++k) out.jtj[k] += g[i] * g[m], size.jtj[k] += std::abs(g[i] * g[m]);
      out.jtr[i] += g[i] * r, size.jtr[i] += std::abs(g[i] * r);
    }
  }
  return out;
}

TEST(PartKernel, TheEllipsesSumsAreTheDefinitionsInBothBuilds) {
  // An old bead's flank under a new bead's points, 0.05 mm apart, noisy:
  // some under the ellipse's top, some where the surface below shows,
  // some off the ellipse; 151 points (a partial last register).
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<double> x, z, old;
  for (int j = 0; j < 151; ++j) {
    x.push_back(-3.8 + 0.05 * j);
    old.push_back(0.4 * std::cos(0.3 * x.back()));
    const double u = (x.back() - 0.1) / 2.9;
    z.push_back(std::max(old.back(), std::abs(u) < 1 ? 0.2 + 1.4 * std::sqrt(1 - u * u) : -1.0) + noise(rng));
  }
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()})
    for (const EllipseAt e : {EllipseAt{0.12, 0.21, 2.85, 1.38, NAN}, EllipseAt{0.05, 0.3, 3.0, 1.5, 0.5}}) {
      SCOPED_TRACE(kernel->name);
      EllipseSums size;
      const EllipseSums want = PointByPoint(x, z, old, e, size);
      const EllipseSums got = kernel->ellipse(x.data(), z.data(), old.data(), 0, x.size(), e);
      // The same terms, each rounded a few times (fused or not), added in
      // another order (four lanes, then across): within 151 additions' and
      // a term's roundings, (151 + 8) 2.2e-16 of the terms' sizes.
      const double eps = 159 * 2.2e-16;
      EXPECT_NEAR(got.rss, want.rss, eps * size.rss);
      for (int k = 0; k < 10; ++k) EXPECT_NEAR(got.jtj[k], want.jtj[k], eps * size.jtj[k]) << k;
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(got.jtr[k], want.jtr[k], eps * size.jtr[k]) << k;
      EXPECT_GT(want.jtj[4], 10.0);  // points under the top counted
    }
}

// The held top's sums four points a register against the table read point
// by point (SuperellipseTable::Locate and S, as part/silhouette_top.cc
// defined them), in both builds: a pressed ellipse's top, 0.05 mm apart,
// noisy, at an exponent off the grid (a pooled one), 113 points (a partial
// last register), the outermost at u = -+0.9 (the table's last entries).
TEST(PartKernel, TheHeldTopsSumsAreTheTablesReadPointByPointInBothBuilds) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  const double x0 = 0.13, a = 2.6, per_a = 1.0 / a;
  const SuperellipseTable& table = SuperellipseOf(2.37);
  std::vector<double> x, z;
  for (int j = 0; j < 113; ++j) {
    x.push_back(x0 - 0.9 * a + 0.05 * j * (1.8 * a / (0.05 * 112)));
    z.push_back(0.4 + 1.3 * table.At((x.back() - x0) * per_a).s + noise(rng));
  }
  const std::size_t lo = 0, hi = x.size();
  TopSums5 want, size;
  for (std::size_t j = lo; j < hi; ++j) {
    int k = 0;
    double t = 0.0;
    SuperellipseTable::Locate((x[j] - x0) * per_a, k, t);
    const double sv = table.S(k, t);
    want.z1 += z[j], want.zz += z[j] * z[j], want.s1 += sv, want.s2 += sv * sv, want.zs += z[j] * sv;
    size.z1 += std::abs(z[j]), size.zs += std::abs(z[j] * sv);
  }
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()}) {
    SCOPED_TRACE(kernel->name);
    const TopSums5 got = kernel->top(x.data(), z.data(), lo, hi, x0, per_a,
                                     {table.entries(), SuperellipseTable::kTabulatedU, SuperellipseTable::kEntries});
    // The same terms (s: one product fused or not), added in another order:
    // within (113 + 8) 2.2e-16 of the terms' sizes.
    const double eps = 121 * 2.2e-16;
    EXPECT_NEAR(got.z1, want.z1, eps * size.z1);
    EXPECT_NEAR(got.zz, want.zz, eps * want.zz);
    EXPECT_NEAR(got.s1, want.s1, eps * want.s1);
    EXPECT_NEAR(got.s2, want.s2, eps * want.s2);
    EXPECT_NEAR(got.zs, want.zs, eps * size.zs);
    EXPECT_GT(want.s1, 0.5 * static_cast<double>(hi - lo));  // the top's s, not zeros
  }
}

// The surface below at many places four a register is SurfaceGrid's own
// (the definition: SampleAt's z), in both builds: one row, and two on
// different grids blended, each with unknown values inside and places off
// either end (NaN there; where one row is unknown, the other stands).
TEST(PartKernel, TheSurfaceBelowAtPlacesIsTheGridsInBothBuilds) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> across(-6.0, 6.0);
  const auto row = [](double x0, double dx, std::size_t n, double phase) {
    SurfaceRow r;
    r.x0_mm = x0, r.dx_mm = dx;
    for (std::size_t k = 0; k < n; ++k) r.z_mm.push_back(static_cast<float>(std::sin(phase + 0.7 * (x0 + dx * k))));
    r.z_mm[n / 3] = NAN;  // a point the sensor lost
    return r;
  };
  const double shift = 0.137;
  std::vector<double> x(203);
  for (double& v : x) v = across(rng);
  x[0] = -40.0, x[7] = 40.0;  // off both rows
  const auto a = std::make_shared<const SurfaceRow>(row(-5.0, 0.05, 190, 0.0));
  const auto b = std::make_shared<const SurfaceRow>(row(-4.02, 0.049, 170, 0.3));
  for (const SurfaceGrid& grid : {SurfaceGrid(*a), SurfaceGrid(a, b, 0.35)}) {
    RowsAt rows;
    rows.count = grid.row(1) ? 2 : 1;
    for (int r = 0; r < rows.count; ++r)
      rows.z[r] = grid.row(r)->z_mm.data(), rows.size[r] = grid.row(r)->z_mm.size(), rows.x0[r] = grid.row(r)->x0_mm,
      rows.per_mm[r] = 1.0 / grid.row(r)->dx_mm;
    rows.shift = shift, rows.w = grid.weight();
    std::size_t unknown = 0;
    for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()}) {
      SCOPED_TRACE(kernel->name);
      std::vector<double> got(x.size());
      kernel->rows_at(x.data(), x.size(), rows, got.data());
      unknown = 0;
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double want = grid.At(x[i] - shift);
        unknown += std::isnan(want);
        if (std::isnan(want)) {
          EXPECT_TRUE(std::isnan(got[i])) << i;
          continue;
        }
        // The index by 1 / dx, not by dx: a few roundings of values of 1.
        EXPECT_NEAR(got[i], want, 1e-12) << i << " at " << x[i];
      }
    }
    EXPECT_GE(unknown, 2u);  // off the rows, and beside the lost point
  }
}

// The gains over rows of measured points (every value one point's
// variance: part/sensor_rows.h) are the surface below and local's sums as
// the kernel gives them over such rows with their variances read (ones),
// in both builds: one row and two blended, a point of the new profile and
// one of a row lost, a shift of a fraction of a spacing.
TEST(PartKernel, TheGainsOverMeasuredRowsAreLocalsSumsAndTheSurfaceBelowInBothBuilds) {
  const std::size_t n = 203;
  const double dx = 0.05;
  std::vector<float> a(n + 20), b(n + 20), ones(n + 20, 1.0f), zn(n);
  for (std::size_t k = 0; k < a.size(); ++k)
    a[k] = static_cast<float>(std::sin(0.7 * dx * k)), b[k] = static_cast<float>(std::sin(0.3 + 0.7 * dx * k));
  b[60] = NAN;
  for (std::size_t i = 0; i < n; ++i) zn[i] = static_cast<float>(std::sin(0.15 + 0.7 * dx * i) + (i % 7) * 0.01);
  zn[100] = NAN;
  const GridShared c{1e-4f, 36.0f, static_cast<float>(1.0 / dx)};
  for (int count : {1, 2}) {
    GridRows rows;
    rows.count = count, rows.w = 0.35f;
    rows.t[0] = 0.37f, rows.t[1] = 0.81f;
    rows.z[0] = a.data() + 3, rows.z[1] = b.data() + 5;
    rows.v[0] = ones.data(), rows.v[1] = ones.data();
    const std::ptrdiff_t begin = 2, end = 190;
    for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()}) {
      SCOPED_TRACE(std::string(kernel->name) + (count == 2 ? ", two rows" : ", one row"));
      std::vector<float> want_below(n, 0.0f), below(n, 0.0f), gain(n, 0.0f);
      kernel->below_at(rows, begin, end, want_below.data());
      const GridSums want = kernel->local(zn.data(), rows, begin, end, c);
      const GridSums got = kernel->gains(zn.data(), rows, begin, end, c, below.data(), gain.data());
      for (std::ptrdiff_t i = begin; i < end; ++i) {
        const auto k = static_cast<std::size_t>(i);
        // The same lerp and blend: to a float's last bits (a compiler may
        // fuse a product and a sum in one and not the other: clang did).
        ASSERT_EQ(std::isnan(below[k]), std::isnan(want_below[k])) << i;
        const float ulps = 4.0f * std::numeric_limits<float>::epsilon();
        if (!std::isnan(want_below[k])) {
          EXPECT_NEAR(below[k], want_below[k], ulps * std::abs(want_below[k])) << i;
        }
        const float d = zn[k] - want_below[k];
        if (std::isnan(d)) {
          EXPECT_TRUE(std::isnan(gain[k])) << i;
        } else {
          EXPECT_NEAR(gain[k], std::max(d, 0.0f), ulps * (std::abs(zn[k]) + std::abs(want_below[k]))) << i;
        }
      }
      // Over the variance by its inverse, not divided: a float's rounding
      // a term, summed over eight lanes.
      EXPECT_NEAR(got.first, want.first, 1e-5 * std::abs(want.first));
      EXPECT_NEAR(got.second, want.second, 1e-5 * std::abs(want.third) * dx + 1e-9);
      EXPECT_NEAR(got.third, want.third, 1e-5 * std::abs(want.third));
      EXPECT_GT(want.third, 0.0);
    }
  }
}

// A profile of n points 0.05 mm apart from x0 over the surface below
// under(x, i), each point its gain bead(x) over it and 0.01 mm of noise.
struct SurfaceProfile {
  std::vector<float> x, z, under;
};
template <class Under, class Bead>
SurfaceProfile OverASurface(std::size_t n, float x0, unsigned seed, Under under, Bead bead) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  SurfaceProfile p{std::vector<float>(n), std::vector<float>(n), std::vector<float>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    p.x[i] = x0 + 0.05f * static_cast<float>(i);
    p.under[i] = under(p.x[i], i);
    p.z[i] = p.under[i] + noise(rng) + bead(p.x[i]);
  }
  return p;
}

// The flanks' counts are their rules written point by point, in both builds.
TEST(PartKernel, TheFlanksAreTheirRulesPointByPointInBothBuilds) {
  const std::size_t n = 301;
  // A bed, then a flank and a top; and a bead.
  auto [x, z, under] = OverASurface(
      n, -7.5f, 11, [](float x, std::size_t) { return x < -2.0f ? 0.0f : 2.0f * std::cos(0.5f * x); },
      [](float x) { return std::abs(x - 1.0f) < 1.0f ? 0.5f : 0.0f; });
  under[150] = NAN;
  const float tau = 0.06f, steep = 0.9f, run = 0.6f;
  double single = 0.0, runs = 0.0;
  for (std::size_t i = 0; i + 2 < n; ++i) {
    const float d = z[i] - under[i], first = under[i + 1] - under[i], second = under[i + 2] - under[i + 1];
    const float step = x[i + 1] - x[i], next = x[i + 2] - x[i + 1];
    if (!(std::abs(d) <= tau)) continue;
    if (std::abs(first) > steep * step)
      ++single;
    else if (std::abs(first) > run * step && first * second > 0.0f && std::abs(second) > run * next)
      ++runs;
  }
  EXPECT_GT(single, 0.0);
  EXPECT_GT(runs, 0.0);
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()}) {
    SCOPED_TRACE(kernel->name);
    const GridSums got = kernel->flanks(x.data(), z.data(), under.data(), n, tau, steep, run);
    EXPECT_EQ(got.first, single);
    EXPECT_EQ(got.second, runs);
  }
}

// The crest (the first greatest median of three, core/median.h's
// Median3 with its order for NaN) against the scalar loop, over ranges of
// every length up to and past a register's eight, on heights quantised to
// a few levels (ties) with NaNs (a sensor's dropouts) among them.
TEST(PartKernel, TheCrestIsTheFirstGreatestMedianOfThreeInBothBuilds) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> level(0, 6), pick(0, 9);
  const std::size_t n = 64;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<float> z(n);
    for (float& v : z) v = pick(rng) == 0 ? NAN : 0.1f * static_cast<float>(level(rng));
    if (trial % 50 == 0) std::fill(z.begin(), z.end(), NAN);  // nothing but dropouts: lo
    for (std::size_t lo = 1; lo < 12; lo += 3) {
      for (std::size_t hi = lo; hi + 1 < n; hi += 5) {
        std::size_t want = lo;
        float top = -std::numeric_limits<float>::infinity();
        for (std::size_t k = lo; k < hi; ++k)
          if (const float m = Median3(z[k - 1], z[k], z[k + 1]); m > top) top = m, want = k;
        for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()})
          ASSERT_EQ(kernel->crest(z.data(), lo, hi), want)
              << kernel->name << " trial " << trial << " [" << lo << ", " << hi << ")";
      }
    }
  }
}

// FlankPoints counts a stretch of points at a time until the first rule
// has enough: with more asked than there are, the whole profile's count
// (the kernel over every point at once, and the last point's first rule);
// with fewer, at least as many as asked, found before the end.
TEST(FlankPoints, CountedStretchByStretchIsTheWholeCountOrEnough) {
  const std::size_t n = 801;
  // Steps of the layer below at -12, 3 and 15 mm (flanks in the first
  // stretch and far past it), one between points 255 and 256 (where two
  // stretches meet) and a ramp at 8 mm (a run: 0.9 mm a mm).
  const auto [x, z, under] = OverASurface(
      n, -20.0f, 3,
      [](float x, std::size_t i) {
        return (x > -12.0f ? 0.4f : 0.0f) + (x > 3.0f ? 0.6f : 0.0f) + (x > 15.0f ? -0.8f : 0.0f) +
               (i > 255 ? 0.3f : 0.0f) + 0.9f * std::clamp(x - 8.0f, 0.0f, 1.0f);
      },
      [](float) { return 0.0f; });
  const RegistrationScale scale{0.06, 0.01, 0.05};
  const double noise_slope = scale.noise / scale.spacing;
  const GridSums all = ActivePartKernel().flanks(x.data(), z.data(), under.data(), n, 0.06f,
                                                 static_cast<float>(4.5 * std::sqrt(2.0) * noise_slope),
                                                 static_cast<float>(3.0 * noise_slope));
  const float d = z[n - 2] - under[n - 2];
  const int last =
      std::abs(d) <= 0.06f && std::abs(under[n - 1] - under[n - 2]) >
                                  static_cast<float>(4.5 * std::sqrt(2.0) * noise_slope) * (x[n - 1] - x[n - 2]);
  const int single = static_cast<int>(all.first) + last, runs = static_cast<int>(all.second);
  ASSERT_GE(single, 3);
  EXPECT_GT(runs, 0);
  EXPECT_EQ(FlankPoints(x, z, under, scale, 1000), single + runs);
  for (int enough : {1, 2, 3}) EXPECT_GE(FlankPoints(x, z, under, scale, enough), enough) << enough;
}

}  // namespace
}  // namespace bead::part

namespace bead::part {
namespace {

// Moved into the bed frame, each value the double sum rounded once (the
// definition, written here point by point), the same bits in both builds;
// a NaN or an infinity anywhere, in x or z, is told; a finite profile is not.
TEST(PartKernel, PointsMovedIntoTheBedFrameAreTheDoubleSumRoundedOnceInBothBuilds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  const std::size_t n = 803;  // a partial last register
  std::vector<float> x(n), z(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = u(rng), z[i] = u(rng);
  const double fx = 123.456789012345, fz = -0.1;  // not floats: the sum's rounding shows
  for (const PartKernel* kernel : {&BaselinePartKernel(), &ActivePartKernel()}) {
    SCOPED_TRACE(kernel->name);
    std::vector<float> ox(n), oz(n);
    EXPECT_FALSE(kernel->to_bed(x.data(), z.data(), n, fx, fz, ox.data(), oz.data()));
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(ox[i], static_cast<float>(static_cast<double>(x[i]) + fx)) << i;
      ASSERT_EQ(oz[i], static_cast<float>(static_cast<double>(z[i]) + fz)) << i;
    }
    for (const float bad : {NAN, INFINITY, -INFINITY})
      for (std::size_t at : {std::size_t{0}, std::size_t{401}, n - 1})
        for (int in_z = 0; in_z < 2; ++in_z) {
          std::vector<float> bx = x, bz = z;
          (in_z ? bz : bx)[at] = bad;
          EXPECT_TRUE(kernel->to_bed(bx.data(), bz.data(), n, fx, fz, ox.data(), oz.data())) << at << " " << bad;
        }
  }
}

}  // namespace
}  // namespace bead::part

namespace bead {
namespace {

// The bits' tests agree with the library's on every kind of value: NaNs
// quiet, signalling and negative, both infinities, zeros of both signs,
// subnormals, the largest finite, ordinary values.
TEST(FloatBits, NanAndFiniteAreToldAsTheLibraryTellsThem) {
  const std::vector<float> floats = {std::numeric_limits<float>::quiet_NaN(),
                                     std::numeric_limits<float>::signaling_NaN(),
                                     -std::numeric_limits<float>::quiet_NaN(),
                                     std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity(),
                                     0.0f,
                                     -0.0f,
                                     std::numeric_limits<float>::denorm_min(),
                                     std::numeric_limits<float>::max(),
                                     -1.5f,
                                     123.25f};
  for (const float v : floats) {
    EXPECT_EQ(IsNanBits(v), std::isnan(v)) << v;
    EXPECT_EQ(IsFiniteBits(v), std::isfinite(v)) << v;
    const auto d = static_cast<double>(v);
    EXPECT_EQ(IsFiniteBits(d), std::isfinite(d)) << d;
  }
  EXPECT_FALSE(IsFiniteBits(std::numeric_limits<double>::signaling_NaN()));
  EXPECT_TRUE(IsFiniteBits(std::numeric_limits<double>::max()));
}

}  // namespace
}  // namespace bead
