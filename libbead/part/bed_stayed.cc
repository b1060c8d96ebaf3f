#include "libbead/part/bed_stayed.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "libbead/core/median.h"

namespace bead::part {
namespace {

// Above layer 0, the median gain over one of the rig's reference areas
// (in the profile's own frame: bare bed in every layer), the surface below
// moved by `shift`; NaN where fewer than kMinReferencePoints points there
// have one (a bed out of the sensor's range under a tall part).
constexpr std::size_t kMinReferencePoints = 10;
double ReferenceGain(const StoredProfile& p, const SurfaceGrid& under, double shift, double frame_x,
                     const ReferenceArea& area) {
  thread_local std::vector<double> gains;
  gains.clear();
  for (std::size_t j = 0; j < p.x_mm.size(); ++j) {
    if (!area.Contains(p.x_mm[j] - frame_x)) continue;
    if (const double gain = p.z_mm[j] - under.At(p.x_mm[j] - shift); std::isfinite(gain)) gains.push_back(gain);
  }
  return gains.size() < kMinReferencePoints ? std::nan("") : MiddleInPlace(gains);
}

// The area's offset: of its gains at the pass's shift and unmoved, the
// lesser (a bed that did not move meets the layer below's scan at one of
// them: unmoved where it is flat, at the shift where it slopes, a pipe;
// where the frames disagree, the shift is any the registration found, and
// the bed off at both).
double ReferenceOffset(const StoredProfile& p, const SurfaceGrid& under, double shift, double frame_x,
                       const ReferenceArea& area) {
  const double unmoved = ReferenceGain(p, under, 0.0, frame_x, area);
  const double moved = ReferenceGain(p, under, shift, frame_x, area);
  if (!std::isfinite(moved)) return unmoved;
  return !std::isfinite(unmoved) || std::abs(moved) < std::abs(unmoved) ? moved : unmoved;
}

}  // namespace

void CheckBedStayed(const StoredProfile& p, const SurfaceGrid& under, double frame_x, const Rig& rig,
                    const AddedBeadOptions& o, AddedBead& bead) {
  if (bead.status == AddedStatus::kUnderSurfaceBelow || !std::isfinite(bead.noise_mm)) return;
  const double tau = std::max(o.min_threshold_mm, o.threshold_sigmas * bead.noise_mm);
  const double left = ReferenceOffset(p, under, bead.shift_mm, frame_x, rig.reference_left);
  const double right = ReferenceOffset(p, under, bead.shift_mm, frame_x, rig.reference_right);
  if (!(std::abs(left) > tau && std::abs(right) > tau && left * right > 0.0 && std::abs(left - right) < tau)) return;
  AddedBead moved;
  moved.status = AddedStatus::kBedMoved;
  moved.bed_off_mm = 0.5 * (left + right), moved.noise_mm = bead.noise_mm, moved.shift_mm = bead.shift_mm;
  bead = moved;
}

}  // namespace bead::part
