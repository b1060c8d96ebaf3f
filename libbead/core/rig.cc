#include "libbead/core/rig.h"

#include <cmath>
#include <numbers>

namespace bead {

double Rig::MmPerCount() const {
  return std::numbers::pi * wheel_diameter_mm / encoder.counts_per_rev;
}

double Rig::SurfaceSpeedFactor(double counts) const {
  if (wheel_eccentricity_mm == 0.0) return 1.0;
  const double theta = 2.0 * std::numbers::pi * counts / encoder.counts_per_rev;
  const double phase = wheel_eccentricity_phase_deg * std::numbers::pi / 180.0;
  return 1.0 + wheel_eccentricity_mm * std::cos(theta - phase) / (0.5 * wheel_diameter_mm);
}

}  // namespace bead
