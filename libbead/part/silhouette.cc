#include "libbead/part/silhouette.h"

#include <algorithm>
#include <cmath>

namespace bead::part {
namespace {

// The top's points within kInner of the half-width are solved over.
constexpr double kInner = 0.9;

// z0 and b (b = aspect a where held) of the ellipse with ends L and R, by
// least squares over the points [first, last] within kInner of the
// half-width; false where too few are, or b is not positive.
bool SolveTop(const Window& w, std::size_t first, std::size_t last, double L, double R, double aspect, Silhouette& s) {
  Ellipse& e = s.e;
  e.x0 = 0.5 * (L + R), e.a = 0.5 * (R - L);
  const bool held = std::isfinite(aspect);
  double m = 0, s1 = 0, s2 = 0, z1 = 0, zs = 0, zz = 0;
  for (std::size_t j = first; j <= last; ++j) {
    const double u = (w.x[j] - e.x0) / e.a;
    if (!(std::abs(u) <= kInner)) continue;
    const double sv = std::sqrt(1.0 - u * u), z = w.z[j];
    m += 1, s1 += sv, s2 += sv * sv, z1 += z, zs += z * sv, zz += z * z;
  }
  const int params = held ? 1 : 2;
  if (m < 3.0 * params + 2.0) return false;
  double rss;
  if (held) {
    e.b = aspect * e.a;
    e.z0 = (z1 - e.b * s1) / m;
    s.z0_var = 1.0 / m, s.b_var = 0.0, s.z0_b = 0.0;
  } else {
    const double det = m * s2 - s1 * s1;
    if (!(det > 0.0)) return false;
    e.b = (m * zs - s1 * z1) / det, e.z0 = (z1 - e.b * s1) / m;
    s.z0_var = s2 / det, s.b_var = m / det, s.z0_b = -s1 / det;
  }
  // The residuals' sum of squares from the sums: sum (z - z0 - b s)^2.
  rss = zz + m * e.z0 * e.z0 + e.b * e.b * s2 - 2.0 * e.z0 * z1 - 2.0 * e.b * zs + 2.0 * e.z0 * e.b * s1;
  s.points = static_cast<int>(m);
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

double SilhouetteVariance(const Window& w, const Silhouette& s, double aspect, double aspect_sigma,
                          const double gradient[4]) {
  // The top's points: those between the two cells.
  const auto first = static_cast<std::size_t>(std::upper_bound(w.x.begin(), w.x.end(), s.cell[0]) - w.x.begin());
  const auto last = static_cast<std::size_t>(std::lower_bound(w.x.begin(), w.x.end(), s.cell[3]) - w.x.begin()) - 1;
  const double L = s.e.x0 - s.e.a, R = s.e.x0 + s.e.a;
  // Each end from one side of its cell to the other: the area seen changes
  // by the wall times the step (less where the left end moves in, more where
  // the right one moves out), the groove as the ellipse re-solved there.
  // (Placing anew the bead each such ellipse would show, its seen area's
  // trapezoids against their integral, gave the same: 0.0099 mm^2 against
  // 0.0096 on part/silhouette_test.cc's beads.)
  double ends = 0.0;
  for (int side = 0; side < 2; ++side) {
    Silhouette lo, hi;
    const double a0 = s.cell[2 * side], a1 = s.cell[2 * side + 1];
    if (!SolveTop(w, first, last, side ? L : a0, side ? a0 : R, aspect, lo) ||
        !SolveTop(w, first, last, side ? L : a1, side ? a1 : R, aspect, hi))
      return NAN;
    const double seen = side ? s.wall_right * (a1 - a0) : -s.wall_left * (a1 - a0);
    const double range = GrooveChange(lo.e, hi.e, gradient) - seen;
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
