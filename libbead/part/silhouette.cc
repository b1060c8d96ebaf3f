#include "libbead/part/silhouette.h"

#include <algorithm>
#include <cmath>

namespace bead::part {
namespace {

// The top's points within kInner of the half-width are solved over.
constexpr double kInner = 0.9;

// z0 and b (b = aspect a where held) of the ellipse with ends L and R, by
// least squares over the points [first, last] within kInner of the
// half-width, and their derivatives in each end's place (the points kept:
// the sums' derivatives through s = sqrt(1 - u^2), u = (x - x0) / a, ds/dx0
// = u / (a s), ds/da = u^2 / (a s), x0 and a each moving by half an end's
// step); false where too few points are, or b is not positive.
bool SolveTop(const Window& w, std::size_t first, std::size_t last, double L, double R, double aspect, Silhouette& s) {
  Ellipse& e = s.e;
  e.x0 = 0.5 * (L + R), e.a = 0.5 * (R - L);
  const bool held = std::isfinite(aspect);
  double m = 0, s1 = 0, s2 = 0, z1 = 0, zs = 0, zz = 0;
  double d1[2] = {}, d2[2] = {}, dz[2] = {};  // the sums s1, s2, zs in x0 and a
  const double per_a = 1.0 / e.a;
  for (std::size_t j = first; j <= last; ++j) {
    const double u = (w.x[j] - e.x0) * per_a;
    if (!(std::abs(u) <= kInner)) continue;
    const double sv = std::sqrt(1.0 - u * u), z = w.z[j];
    m += 1, s1 += sv, s2 += sv * sv, z1 += z, zs += z * sv, zz += z * z;
    const double by_x0 = u * per_a / sv, by[2] = {by_x0, u * by_x0};
    for (int i = 0; i < 2; ++i) d1[i] += by[i], d2[i] += 2.0 * sv * by[i], dz[i] += z * by[i];
  }
  const int params = held ? 1 : 2;
  if (m < 3.0 * params + 2.0) return false;
  const double det = m * s2 - s1 * s1;
  if (held) {
    e.b = aspect * e.a;
    e.z0 = (z1 - e.b * s1) / m;
    s.z0_var = 1.0 / m, s.b_var = 0.0, s.z0_b = 0.0;
  } else {
    if (!(det > 0.0)) return false;
    e.b = (m * zs - s1 * z1) / det, e.z0 = (z1 - e.b * s1) / m;
    s.z0_var = s2 / det, s.b_var = m / det, s.z0_b = -s1 / det;
  }
  for (int end = 0; end < 2; ++end) {
    // The left end moves x0 by half its step and a by minus half; the right, both by half.
    const double by_x0 = 0.5, by_a = end ? 0.5 : -0.5;
    const double ds1 = d1[0] * by_x0 + d1[1] * by_a, ds2 = d2[0] * by_x0 + d2[1] * by_a;
    const double dzs = dz[0] * by_x0 + dz[1] * by_a;
    if (held) {
      s.b_by_end[end] = aspect * by_a;
      s.z0_by_end[end] = -(s.b_by_end[end] * s1 + e.b * ds1) / m;
    } else {
      const double r0 = -ds1 * e.b, r1 = dzs - ds1 * e.z0 - ds2 * e.b;
      s.z0_by_end[end] = (s2 * r0 - s1 * r1) / det, s.b_by_end[end] = (m * r1 - s1 * r0) / det;
    }
  }
  // The residuals' sum of squares from the sums: sum (z - z0 - b s)^2.
  const double rss = zz + m * e.z0 * e.z0 + e.b * e.b * s2 - 2.0 * e.z0 * z1 - 2.0 * e.b * zs + 2.0 * e.z0 * e.b * s1;
  s.residual_variance = std::max(rss, 0.0) / (m - params);
  s.mean_s = s1 / m;
  return e.b > 0.0 && std::isfinite(e.z0);
}

// The surface below at x, between the window's points j and j + 1.
double OldBetween(const Window& w, std::size_t j, double x) {
  const double t = (x - w.x[j]) / (w.x[j + 1] - w.x[j]);
  return w.old[j] + t * (w.old[j + 1] - w.old[j]);
}

// The groove's change from `from` to `to`, linear in the parameters.
double GrooveChange(const Ellipse& from, const Ellipse& to, const double gradient[4]) {
  double change = 0.0;
  for (std::size_t i = 0; i < 4; ++i) change += gradient[i] * (to[i] - from[i]);
  return change;
}

}  // namespace

std::optional<Silhouette> AtSilhouette(const Window& w, double center, const SilhouetteScale& k, double aspect) {
  const std::size_t n = w.x.size();
  const auto c = static_cast<std::size_t>(std::lower_bound(w.x.begin(), w.x.end(), center) - w.x.begin());
  if (c >= n || !(w.Gain(c) > k.floor)) return std::nullopt;
  // The run around the centre standing over the floor.
  std::size_t l = c, r = c;
  while (l > 0 && w.Gain(l - 1) > k.floor) --l;
  while (r + 1 < n && w.Gain(r + 1) > k.floor) ++r;
  if (l == 0 || r + 1 == n || r - l < 8) return std::nullopt;
  // Each side's largest rise from one point to the next, in the run's
  // outer third (from the bare point beside it).
  const std::size_t third = (r - l) / 3;
  std::size_t jl = l - 1, jr = r;
  double rise_l = -INFINITY, rise_r = -INFINITY;
  for (std::size_t j = l - 1; j < l + third; ++j)
    if (const double rise = w.Gain(j + 1) - w.Gain(j); rise > rise_l) rise_l = rise, jl = j;
  for (std::size_t j = r - third; j <= r; ++j)
    if (const double rise = w.Gain(j) - w.Gain(j + 1); rise > rise_r) rise_r = rise, jr = j;
  if (!(rise_l > k.rise && rise_r > k.rise)) return std::nullopt;
  Silhouette s;
  s.cell[0] = w.x[jl], s.cell[1] = w.x[jl + 1], s.cell[2] = w.x[jr], s.cell[3] = w.x[jr + 1];
  const double L = 0.5 * (s.cell[0] + s.cell[1]), R = 0.5 * (s.cell[2] + s.cell[3]);
  if (!SolveTop(w, jl + 1, jr, L, R, aspect, s)) return std::nullopt;
  s.wall_left = s.e.z0 - OldBetween(w, jl, L);
  s.wall_right = s.e.z0 - OldBetween(w, jr, R);
  // The ellipse's widest point standing over the surface below by a wall
  // at each end: an overhang. (A bead whose sides meet the surface, seen at
  // points far apart, rises as steeply from one to the next; placed there,
  // its widest point lies on the surface.)
  if (!(s.wall_left > k.rise && s.wall_right > k.rise)) return std::nullopt;
  return s;
}

double SilhouetteVariance(const Silhouette& s, double aspect, double aspect_sigma, const double gradient[4]) {
  // Each end from one side of its cell to the other: the area seen changes
  // by the wall times the step (less where the left end moves in, more where
  // the right one moves out), the groove as the ellipse re-solved there
  // (linear in the step: z0 and b by their derivatives in the end's place).
  // (Placing anew the bead each such ellipse would show, its seen area's
  // trapezoids against their integral, gave the same: 0.0099 mm^2 against
  // 0.0096 on part/silhouette_test.cc's beads.)
  double ends = 0.0;
  for (int side = 0; side < 2; ++side) {
    const double step = s.cell[2 * side + 1] - s.cell[2 * side];
    Ellipse moved = s.e;
    moved.x0 += 0.5 * step, moved.a += (side ? 0.5 : -0.5) * step;
    moved.z0 += s.z0_by_end[side] * step, moved.b += s.b_by_end[side] * step;
    const double seen = (side ? s.wall_right : -s.wall_left) * step;
    const double range = GrooveChange(s.e, moved, gradient) - seen;
    ends += range * range / 12.0;
  }
  // z0 and b to their covariance.
  const double g_z0 = gradient[1], g_b = gradient[3];
  const double solved =
      s.residual_variance * (g_z0 * g_z0 * s.z0_var + 2.0 * g_z0 * g_b * s.z0_b + g_b * g_b * s.b_var);
  // A held aspect a sigma off: b moves by a sigma, z0 by the mean of s
  // times that, the other way.
  const double by_aspect =
      std::isfinite(aspect) && aspect_sigma > 0.0 ? (g_b - g_z0 * s.mean_s) * s.e.a * aspect_sigma : 0.0;
  return ends + solved + by_aspect * by_aspect;
}

}  // namespace bead::part
