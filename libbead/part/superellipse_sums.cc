#include "libbead/part/superellipse_sums.h"

#include <algorithm>
#include <cmath>

#include "libbead/part/superellipse.h"

namespace bead::part {
namespace {
// The slope held at 50, as the ellipse's is at s >= 0.02 (u / s <= 50).
constexpr double kMaxSlope = 50.0;
}  // namespace

// One point at a time: the derivatives as the ellipse's with s' = ds/du for
// -u / s (the table's within its reach, exact beyond).
EllipseSums SuperellipseSums(const Window& w, std::size_t lo, std::size_t hi, const Ellipse& e, double aspect) {
  const SuperellipseTable& table = SuperellipseOf(e.p);
  const bool held = std::isfinite(aspect);
  const int params = held ? 3 : 4;
  EllipseSums sums;
  for (std::size_t j = lo; j < hi; ++j) {
    const double u = (w.x[j] - e.x0) / e.a;
    if (!(std::abs(u) < 1.0)) {
      sums.rss += (w.old[j] - w.z[j]) * (w.old[j] - w.z[j]);
      continue;
    }
    const SuperellipseTable::Value v =
        std::abs(u) <= SuperellipseTable::kTabulatedU ? table.At(u) : SuperellipseAt(u, e.p);
    const double top = e.z0 + e.b * v.s;
    const bool seen = top > w.old[j];
    const double r = (seen ? top : w.old[j]) - w.z[j];
    sums.rss += r * r;
    if (!seen) continue;
    const double by_x0 = -e.b * std::clamp(v.ds_du, -kMaxSlope, kMaxSlope) / e.a;
    const double g[4] = {by_x0, 1.0, by_x0 * u + (held ? aspect * v.s : 0.0), held ? 0.0 : v.s};
    for (int i = 0, n = 0; i < params; n += 4 - i, ++i) {
      for (int k = i; k < params; ++k) sums.jtj[n + k - i] += g[i] * g[k];
      sums.jtr[i] += g[i] * r;
    }
  }
  return sums;
}

}  // namespace bead::part
