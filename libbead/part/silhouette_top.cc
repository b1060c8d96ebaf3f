#include "libbead/part/silhouette_top.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "libbead/part/part_kernel.h"
#include "libbead/part/superellipse.h"
#include "libbead/part/top_sums.h"

namespace bead::part {
namespace {

// The top's points within kInner of the half-width are solved over (where
// the exponent's table holds s).
constexpr double kInner = SuperellipseTable::kTabulatedU;

}  // namespace

std::pair<std::size_t, std::size_t> TopRange(const Window& w, std::size_t first, std::size_t last, double L, double R) {
  const double x0 = 0.5 * (L + R), per_a = 2.0 / (R - L);
  const auto u_at = [&](std::size_t j) { return (w.x[j] - x0) * per_a; };
  const auto first_where = [&](std::size_t a, auto above) {
    std::size_t b = last + 1;
    while (a < b) {
      const std::size_t m = a + (b - a) / 2;
      if (above(u_at(m)))
        b = m;
      else
        a = m + 1;
    }
    return a;
  };
  const std::size_t lo = first_where(first, [](double u) { return u >= -kInner; });
  return {lo, first_where(lo, [](double u) { return u > kInner; })};
}

namespace {

// Each of the top's points within kInner of the half-width of the bead
// with ends L and R, to keep(j, u) in order.
template <class Keep>
void ForEachTopPoint(const Window& w, std::size_t first, std::size_t last, double L, double R, Keep keep) {
  const double x0 = 0.5 * (L + R), per_a = 2.0 / (R - L);
  const auto u_at = [&](std::size_t j) { return (w.x[j] - x0) * per_a; };
  if (!(per_a > 0.0)) {
    for (std::size_t j = first; j <= last; ++j)
      if (const double u = u_at(j); std::abs(u) <= kInner) keep(j, u);
    return;
  }
  const auto [lo, hi] = TopRange(w, first, last, L, R);
  for (std::size_t j = lo; j < hi; ++j) keep(j, u_at(j));
}

}  // namespace

const TopPoints& TopOf(const Window& w, std::size_t first, std::size_t last, double L, double R) {
  thread_local TopPoints p;
  const std::size_t most = last >= first ? last - first + 1 : 0;
  p.u.resize(most), p.z.resize(most), p.t.resize(most), p.k.resize(most);
  p.per_a = 2.0 / (R - L);
  std::size_t n = 0;
  ForEachTopPoint(w, first, last, L, R, [&](std::size_t j, double u) {
    SuperellipseTable::Locate(u, p.k[n], p.t[n]);
    p.u[n] = u, p.z[n] = w.z[j], ++n;
  });
  p.u.resize(n), p.z.resize(n), p.t.resize(n), p.k.resize(n);
  return p;
}

TopSums SumTop(const TopPoints& p, const SuperellipseTable& t) {
  TopSums m;
  m.m = static_cast<double>(p.u.size());
  for (std::size_t j = 0; j < p.u.size(); ++j) {
    const double z = p.z[j];
    m.z1 += z, m.zz += z * z;
    const SuperellipseTable::Value v = t.At(p.k[j], p.t[j], p.u[j] < 0.0);
    const double sv = v.s;
    m.s1 += sv, m.s2 += sv * sv, m.zs += z * sv, m.sp += v.ds_dp;
    const double by_x0 = -v.ds_du * p.per_a, by[2] = {by_x0, p.u[j] * by_x0};
    for (int i = 0; i < 2; ++i) m.d1[i] += by[i], m.d2[i] += 2.0 * sv * by[i], m.dz[i] += z * by[i];
  }
  return m;
}

namespace {

// z0 with b held, from the sums.
double HeldZ0(const TopSums& t, double b) { return (t.z1 - b * t.s1) / t.m; }

// The residuals' sum of squares from the sums: sum (z - z0 - b s)^2.
double ResidualSum(const TopSums& t, double z0, double b) {
  return t.zz + t.m * z0 * z0 + b * b * t.s2 - 2.0 * z0 * t.z1 - 2.0 * b * t.zs + 2.0 * z0 * b * t.s1;
}

// z0 and b solved free from the sums (det: m s2 - s1^2, positive).
void FreeZ0B(const TopSums& t, double det, double& z0, double& b) {
  b = (t.m * t.zs - t.s1 * t.z1) / det, z0 = (t.z1 - b * t.s1) / t.m;
}

}  // namespace

FreeTop FreeResidual(const TopSums& t) {
  const double det = t.m * t.s2 - t.s1 * t.s1;
  if (t.m < 8.0 || !(det > 0.0)) return {};
  double z0 = 0.0, b = 0.0;
  FreeZ0B(t, det, z0, b);
  if (!(b > 0.0)) return {};
  return {std::max(ResidualSum(t, z0, b), 0.0) / (t.m - 2.0), z0, b};
}

bool SolveTop(const TopSums& t, double L, double R, double aspect, Silhouette& s) {
  Ellipse& e = s.e;
  e.x0 = 0.5 * (L + R), e.a = 0.5 * (R - L);
  const bool held = std::isfinite(aspect);
  const int params = held ? 1 : 2;
  if (t.m < 3.0 * params + 2.0) return false;
  const double det = t.m * t.s2 - t.s1 * t.s1;
  if (held) {
    e.b = aspect * e.a;
    e.z0 = HeldZ0(t, e.b);
    s.z0_var = 1.0 / t.m, s.b_var = 0.0, s.z0_b = 0.0;
    s.z0_by_exponent = -e.b * t.sp / t.m;
  } else {
    if (!(det > 0.0)) return false;
    FreeZ0B(t, det, e.z0, e.b);
    s.z0_var = t.s2 / det, s.b_var = t.m / det, s.z0_b = -t.s1 / det;
    s.z0_by_exponent = 0.0;
  }
  for (int end = 0; end < 2; ++end) {
    // The left end moves x0 by half its step and a by minus half; the right, both by half.
    const double by_x0 = 0.5, by_a = end ? 0.5 : -0.5;
    const double ds1 = t.d1[0] * by_x0 + t.d1[1] * by_a, ds2 = t.d2[0] * by_x0 + t.d2[1] * by_a;
    const double dzs = t.dz[0] * by_x0 + t.dz[1] * by_a;
    if (held) {
      s.b_by_end[end] = aspect * by_a;
      s.z0_by_end[end] = -(s.b_by_end[end] * t.s1 + e.b * ds1) / t.m;
    } else {
      const double r0 = -ds1 * e.b, r1 = dzs - ds1 * e.z0 - ds2 * e.b;
      s.z0_by_end[end] = (t.s2 * r0 - t.s1 * r1) / det, s.b_by_end[end] = (t.m * r1 - t.s1 * r0) / det;
    }
  }
  s.residual_variance = std::max(ResidualSum(t, e.z0, e.b), 0.0) / (t.m - params);
  s.mean_s = t.s1 / t.m;
  return e.b > 0.0 && std::isfinite(e.z0);
}

std::pair<std::size_t, std::size_t> OnTheTop(const Window& w, std::size_t first, std::size_t last, double z0,
                                             double sigma_mm, const bool gapped[2], double cell[4], bool* mixed) {
  const double off = z0 - 3.0 * sigma_mm;
  const std::size_t middle = first + (last - first) / 2;
  std::size_t on[2] = {first, last};
  for (int side = 0; side < 2; ++side) {
    if (gapped[side]) continue;
    const double inner = cell[side ? 2 : 1], outer = cell[side ? 3 : 0];
    std::size_t& k = on[side];
    while ((side ? k > middle : k < middle) && !(w.z[k] >= off)) k = side ? k - 1 : k + 1;
    if (!(w.z[k] >= off))
      k = side ? last : first;  // none on its half of the top: nothing to say where the end is
    else if (side)
      cell[2] = std::min(cell[2], w.x[k]);
    else
      cell[1] = std::max(cell[1], w.x[k]);
    // The cell's outer point standing over the surface below (by over
    // three sigmas): a mix of the wall's foot and the end beyond it, which
    // then lies out to the point past it.
    const bool past = side ? last + 2 < w.x.size() : first >= 2;
    const std::size_t bare = side ? last + 1 : first - 1;
    if (past && w.z[bare] - w.old[bare] > 3.0 * sigma_mm) cell[side ? 3 : 0] = w.x[side ? bare + 1 : bare - 1];
    if (mixed) mixed[side] = cell[side ? 2 : 1] != inner || cell[side ? 3 : 0] != outer;
  }
  return {on[0], on[1]};
}

// The shape held: solved at it.
bool SolveHeld(const Window& w, std::size_t first, std::size_t last, double L, double R, const PooledShape& held,
               Silhouette& s) {
  const SuperellipseTable& t = SuperellipseOf(held.exponent);
  const double aspect = held.AspectAt(0.5 * (R - L));
  if (!SolveTop(SumTop(TopOf(w, first, last, L, R), t), L, R, aspect, s)) return false;
  s.e.p = held.exponent, s.exponent = held.exponent;
  s.aspect = std::isfinite(aspect) ? aspect : s.e.b / s.e.a;
  return true;
}

TopSums TableSums(const Window& w, std::size_t first, std::size_t last, double L, double R,
                  const SuperellipseTable& table) {
  if (!(R > L)) return {};  // (R > L: the top's points one range)
  return TableSumsOver(w, TopRange(w, first, last, L, R), L, R, table);
}

TopSums TableSumsOver(const Window& w, std::pair<std::size_t, std::size_t> range, double L, double R,
                      const SuperellipseTable& table) {
  TopSums t;
  if (!(R > L)) return t;
  const auto [lo, hi] = range;
  const TopSums5 sums = ActivePartKernel().top(w.x.data(), w.z.data(), lo, hi, 0.5 * (L + R), 2.0 / (R - L),
                                               {table.entries(), kInner, SuperellipseTable::kEntries});
  t.m = static_cast<double>(hi - lo), t.z1 = sums.z1, t.zz = sums.zz, t.s1 = sums.s1, t.s2 = sums.s2, t.zs = sums.zs;
  return t;
}

double HeldTopVariance(const Window& w, std::size_t first, std::size_t last, double L, double R,
                       const PooledShape& held, std::size_t& points, const std::pair<std::size_t, std::size_t>* range) {
  points = 0;
  const double b = held.AspectAt(0.5 * (R - L)) * 0.5 * (R - L);
  if (!(b > 0.0)) return INFINITY;
  const SuperellipseTable& table = SuperellipseOf(held.exponent);
  const TopSums t = range ? TableSumsOver(w, *range, L, R, table) : TableSums(w, first, last, L, R, table);
  points = static_cast<std::size_t>(t.m);
  const double z0 = HeldZ0(t, b);
  if (t.m < 5.0 || !std::isfinite(z0)) return INFINITY;
  return std::max(ResidualSum(t, z0, b), 0.0) / (t.m - 1.0);
}

std::size_t TopPointCount(const Window& w, std::size_t first, std::size_t last, double L, double R) {
  std::size_t n = 0;  // (counted, not written out: TopOf)
  ForEachTopPoint(w, first, last, L, R, [&n](std::size_t, double) { ++n; });
  return n;
}

namespace {

// Where the held shape's top places an end, in steps from the first
// place, from its residual variances var at places a step apart: the
// vertex of the parabola through the least and its neighbours (within half
// a step of the least), and that place's variance, least squares' 2
// sigma^2 / (d2 rss / dE^2): the top's m points' rss = (m - 1) var,
// sigma^2 the least var, so sigma_E^2 = 2 var step^2 / ((m - 1) curve);
// INFINITY where the least has no neighbour either side or the residual is
// not curved upward there. to_edge: a least at the first or last place is
// refined too, by the parabola through the three places nearest that edge
// (its vertex up to a step and a half from their middle).
TopPlace ParabolaOfLeast(const std::vector<double>& var, const std::vector<std::size_t>& points, std::size_t best,
                         double step, bool to_edge) {
  TopPlace p{static_cast<double>(best)};
  const std::size_t c = to_edge && var.size() >= 3 ? std::clamp<std::size_t>(best, 1, var.size() - 2) : best;
  if (c == 0 || c + 1 >= var.size() || !std::isfinite(var[c - 1]) || !std::isfinite(var[c + 1])) return p;
  const double curve = var[c - 1] - 2.0 * var[c] + var[c + 1];
  if (!(curve > 0.0)) return p;
  const double reach = c == best ? 0.5 : 1.5;
  p.at = static_cast<double>(c) + std::clamp(0.5 * (var[c - 1] - var[c + 1]) / curve, -reach, reach);
  const auto m = static_cast<double>(points[best]);
  if (m > 1.0) p.sigma2 = 2.0 * var[best] * step * step / ((m - 1.0) * curve);
  return p;
}

}  // namespace

std::optional<TopPlace> SearchCell(const Window& w, std::size_t first, std::size_t last, double spacing,
                                   const PooledShape& held, int side, bool same_points, double L, double R,
                                   const Silhouette& s) {
  double& end = side ? R : L;
  const double lo = s.cell[2 * side], hi = s.cell[2 * side + 1];
  const int steps = std::max(3, static_cast<int>(std::ceil((hi - lo) / (0.25 * spacing))));
  const double step = (hi - lo) / steps;
  // (Reused call after call: four of them a row.)
  thread_local std::vector<double> var;
  thread_local std::vector<std::size_t> points;
  var.assign(static_cast<std::size_t>(steps), INFINITY), points.assign(var.size(), 0);
  end = side ? lo : hi;  // (the inner edge: the top's fewest points)
  const std::pair<std::size_t, std::size_t> top =
      same_points ? TopRange(w, first, last, L, R) : std::pair{first, first};
  for (int k = 0; k < steps; ++k) {
    const auto i = static_cast<std::size_t>(k);
    end = lo + (k + 0.5) * step;
    if (std::isfinite(held.aspect)) {
      var[i] = HeldTopVariance(w, first, last, L, R, held, points[i], same_points ? &top : nullptr);
      continue;
    }
    // (A layer's pool always holds a finite aspect: b is solved here only
    // for a shape that holds its exponent alone.)
    Silhouette trial = s;
    if (SolveHeld(w, first, last, L, R, held, trial))
      var[i] = trial.residual_variance, points[i] = TopPointCount(w, first, last, L, R);
  }
  const auto best = static_cast<std::size_t>(std::min_element(var.begin(), var.end()) - var.begin());
  if (!std::isfinite(var[best])) return std::nullopt;
  TopPlace place = ParabolaOfLeast(var, points, best, step, same_points);
  place.at = std::clamp(lo + (place.at + 0.5) * step, lo, hi);
  return place;
}

}  // namespace bead::part
