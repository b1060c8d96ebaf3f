#include "libbead/profile/gather.h"

#include <algorithm>
#include <cmath>

namespace bead {

void GatherPoints(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                  ProfileWorkspace& w) {
  w.left_x.clear();
  w.left_z.clear();
  w.right_x.clear();
  w.right_z.clear();
  w.order.clear();
  bool increasing = true, decreasing = true;
  float last = 0.0f;
  const std::size_t n = view.x_mm.size();
  for (std::size_t i = 0; i < n; ++i) {
    const float x = view.x_mm[i];
    const float z = view.z_mm[i];
    if (!std::isfinite(x) || !std::isfinite(z)) continue;
    if (!w.order.empty()) {
      increasing = increasing && x >= last;
      decreasing = decreasing && x <= last;
    }
    last = x;
    w.order.push_back(static_cast<int32_t>(i));
    if (left.Contains(x)) {
      w.left_x.push_back(x);
      w.left_z.push_back(z);
    } else if (right.Contains(x)) {
      w.right_x.push_back(x);
      w.right_z.push_back(z);
    }
  }
  if (increasing) return;
  if (decreasing) {
    std::reverse(w.order.begin(), w.order.end());
    return;
  }
  std::stable_sort(w.order.begin(), w.order.end(),
                   [&](int32_t a, int32_t b) { return view.x_mm[a] < view.x_mm[b]; });
}

}  // namespace bead
