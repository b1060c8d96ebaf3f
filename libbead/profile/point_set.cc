#include "libbead/profile/point_set.h"

#include <algorithm>

#include "libbead/profile/kernel.h"
#include "libbead/profile/vec8.h"

namespace bead {
namespace BEAD_KERNEL {
namespace {

// Whether every x is finite and none is below its predecessor: each x
// must be >= the one before (false for NaN), and with the first and last
// finite, so is every x between.
bool FiniteAndIncreasing(const float* xs, std::size_t n) {
  using namespace vec;
  if (n == 0) return true;
  if (!((xs[0] - xs[0]) == 0.0f) || !((xs[n - 1] - xs[n - 1]) == 0.0f)) return false;
  M8 ordered = ~M8{};
  std::size_t i = 1;
#pragma GCC unroll 4
  for (; i + 8 <= n; i += 8) ordered &= Load(xs + i) >= Load(xs + i - 1);  // one reduction at the end
  if (i < n && n >= 9) {
    ordered &= Load(xs + n - 8) >= Load(xs + n - 9);  // the last eight pairs, some again
    i = n;
  }
  bool tail = true;
  for (; i < n; ++i) tail &= xs[i] >= xs[i - 1];
  return tail && All(ordered);
}

// The points with finite x in increasing x (ties in view order), through w.map.
// A non-finite z stays, as the dropout it is: a profile and its reverse
// then give the same point set.
PointSet SortedCopy(const float* xs, const float* zs, std::size_t n, ProfileWorkspace& w) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i)
    if ((xs[i] - xs[i]) == 0.0f) w.map[m++] = static_cast<int32_t>(i);
  int32_t* map = w.map.data();
  bool increasing = true, decreasing = true;
  for (std::size_t k = 1; k < m; ++k) {
    increasing &= xs[map[k]] >= xs[map[k - 1]];
    decreasing &= xs[map[k]] <= xs[map[k - 1]];
  }
  if (increasing) {
    // In order already, NaN x at the dropouts (a fan sensor's usual
    // profile): the finite points are taken as they come, without a sort.
  } else if (decreasing) {
    // Reversed order; reversing keeps ties in reverse view order, which
    // the geometry does not depend on.
    std::reverse(map, map + m);
  } else {
    std::sort(map, map + m, [&](int32_t a, int32_t b) { return xs[a] < xs[b] || (xs[a] == xs[b] && a < b); });
  }
  for (std::size_t k = 0; k < m; ++k) {
    w.x[k] = xs[map[k]];
    w.z[k] = zs[map[k]];
  }
  w.mapped = true;
  return PointSet{w.x.data(), w.z.data(), m};
}

}  // namespace

PointSet PreparePoints(const ProfileView& view, ProfileWorkspace& w) {
  const std::size_t n = view.x_mm.size();
  if (n > w.capacity()) w.Reserve(n);
  w.mapped = false;
  const float* xs = view.x_mm.data();
  const float* zs = view.z_mm.data();
  // Every later stage reads z, the first ones at scattered places: ask for
  // all of it now (a profile fresh from memory then arrives while x is
  // being checked).
#pragma GCC unroll 4
  for (std::size_t i = 0; i < n; i += 16) __builtin_prefetch(zs + i);
  if (FiniteAndIncreasing(xs, n)) return PointSet{xs, zs, n};
  return SortedCopy(xs, zs, n, w);
}

std::size_t CountFiniteZ(const PointSet& p, std::size_t begin, std::size_t end) {
  using namespace vec;
  M8 finite{};
  std::size_t i = begin;
  for (; i + 8 <= end; i += 8) {
    const V8 z = Load(p.z + i);
    finite += (z - z) == 0.0f;  // lanes are -1 where true
  }
  if (i < end && end - begin >= 8) {
    // The last eight points, without the lanes already counted.
    const V8 z = Load(p.z + end - 8);
    finite += ((z - z) == 0.0f) & LanesFrom(end - 8, i);
    i = end;
  }
  auto count = static_cast<std::size_t>(-SumInt(finite));
  for (; i < end; ++i) count += (p.z[i] - p.z[i]) == 0.0f;
  return count;
}

}  // namespace BEAD_KERNEL
}  // namespace bead
