#include "libbead/profile/gather.h"

#include <algorithm>
#include <cmath>

namespace bead {

void GatherPoints(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                  ProfileWorkspace& w) {
  const std::size_t n = view.x_mm.size();
  if (n > w.capacity()) w.Reserve(n);
  int32_t* order = w.order.data();
  double *lx = w.left_x.data(), *lz = w.left_z.data(), *rx = w.right_x.data(), *rz = w.right_z.data();
  std::size_t nv = 0, nl = 0, nr = 0;
  const float* xs = view.x_mm.data();
  const float* zs = view.z_mm.data();
  bool increasing = true, decreasing = true;
  float last = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = xs[i];
    const float z = zs[i];
    // x - x and z - z are NaN for NaN and infinities: one test for both.
    if (!((x - x) == 0.0f && (z - z) == 0.0f)) continue;
    increasing &= nv == 0 || x >= last;
    decreasing &= nv == 0 || x <= last;
    last = x;
    order[nv++] = static_cast<int32_t>(i);
    if (left.Contains(x)) {
      lx[nl] = x;
      lz[nl++] = z;
    } else if (right.Contains(x)) {
      rx[nr] = x;
      rz[nr++] = z;
    }
  }
  w.n_valid = nv;
  w.n_left = nl;
  w.n_right = nr;
  if (increasing) return;
  if (decreasing) {
    std::reverse(order, order + nv);
    return;
  }
  std::stable_sort(order, order + nv, [&](int32_t a, int32_t b) { return xs[a] < xs[b]; });
}

}  // namespace bead
