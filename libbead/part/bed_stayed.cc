#include "libbead/part/bed_stayed.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "libbead/core/median.h"

namespace bead::part {
namespace {

// Above layer 0, the median gain over one of the rig's reference areas
// (in the profile's own frame: bare bed in every layer), the surface below
// moved by `shift`, over about kSampled of the points there, evenly spread
// (a flat bed's offset by a median of a dozen or two: as good as of all
// of them, at a fraction of the cost); NaN where fewer than
// kMinReferencePoints have a surface below (a bed out of the sensor's
// range under a tall part).
constexpr std::size_t kMinReferencePoints = 10, kSampled = 24;
double ReferenceGain(const StoredProfile& p, const SurfaceGrid& under, double shift, double frame_x,
                     const ReferenceArea& area) {
  thread_local std::vector<double> gains;
  gains.clear();
  const auto first = std::lower_bound(p.x_mm.begin(), p.x_mm.end(), area.x_min_mm + frame_x) - p.x_mm.begin();
  const auto end = std::upper_bound(p.x_mm.begin(), p.x_mm.end(), area.x_max_mm + frame_x) - p.x_mm.begin();
  const auto count = static_cast<std::size_t>(std::max<std::ptrdiff_t>(end - first, 0));
  const std::size_t stride = std::max<std::size_t>(1, count / kSampled);
  for (auto j = static_cast<std::size_t>(first); j < static_cast<std::size_t>(end); j += stride)
    if (const double gain = p.z_mm[j] - under.At(p.x_mm[j] - shift); std::isfinite(gain)) gains.push_back(gain);
  return gains.size() < kMinReferencePoints ? std::nan("") : MiddleInPlace(gains);
}

// Whether the area lies off the layer below's scan of it by over tau at
// the pass's shift and unmoved too (a bed that did not move meets the
// layer below's scan at one of them: unmoved where it is flat, at the shift
// where it slopes, a pipe; where the frames disagree, the shift is any the
// registration found, and the bed off at both); `off` the lesser offset.
bool AreaOff(const StoredProfile& p, const SurfaceGrid& under, double shift, double frame_x, const ReferenceArea& area,
             double tau, double& off) {
  const double moved = ReferenceGain(p, under, shift, frame_x, area);
  if (std::abs(moved) <= tau) return false;
  const double unmoved = ReferenceGain(p, under, 0.0, frame_x, area);
  if (std::abs(unmoved) <= tau) return false;
  off = !std::isfinite(moved) || std::abs(unmoved) < std::abs(moved) ? unmoved : moved;
  return std::isfinite(off);
}

}  // namespace

void CheckBedStayed(const StoredProfile& p, const SurfaceGrid& under, double frame_x, const Rig& rig,
                    const AddedBeadOptions& o, AddedBead& bead) {
  if (bead.status == AddedStatus::kUnderSurfaceBelow || !std::isfinite(bead.noise_mm)) return;
  const double tau = o.Threshold(bead.noise_mm);
  double left = 0.0, right = 0.0;
  if (!AreaOff(p, under, bead.shift_mm, frame_x, rig.reference_left, tau, left) ||
      !AreaOff(p, under, bead.shift_mm, frame_x, rig.reference_right, tau, right))
    return;
  if (!(left * right > 0.0 && std::abs(left - right) < tau)) return;
  AddedBead moved;
  moved.status = AddedStatus::kBedMoved;
  moved.bed_off_mm = 0.5 * (left + right), moved.noise_mm = bead.noise_mm, moved.shift_mm = bead.shift_mm;
  bead = moved;
}

}  // namespace bead::part
