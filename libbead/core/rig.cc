#include "libbead/core/rig.h"

#include <cmath>
#include <numbers>

namespace bead {

double Rig::MmPerCount() const { return std::numbers::pi * wheel_diameter_mm / encoder.counts_per_rev; }

double Rig::SurfaceSpeedFactor(double counts) const {
  if (wheel_eccentricity_mm == 0.0) return 1.0;
  const double theta = 2.0 * std::numbers::pi * counts / encoder.counts_per_rev;
  const double phase = wheel_eccentricity_phase_deg * std::numbers::pi / 180.0;
  return 1.0 + wheel_eccentricity_mm * std::cos(theta - phase) / (0.5 * wheel_diameter_mm);
}

namespace {

bool Broken(std::string* key, std::string* error, const char* k, const std::string& what) {
  if (key) *key = k;
  if (error) *error = what;
  return false;
}

// The wheel's sections: encoder, wheel, offset.
bool WheelIsValid(const Rig& r, std::string* key, std::string* error) {
  const EncoderSpec& e = r.encoder;
  if (!(std::isfinite(e.counts_per_rev) && e.counts_per_rev > 0))
    return Broken(key, error, "encoder.counts_per_rev", "must be positive");
  if (e.bits < 0 || e.bits > 64 || (e.bits > 0 && e.bits < 8))
    return Broken(key, error, "encoder.bits",
                  "must be 0 (never wraps) or a counter width from 8 to 64, got " + std::to_string(e.bits));
  if (e.direction != 1 && e.direction != -1)
    return Broken(key, error, "encoder.direction", "must be 1 or -1, got " + std::to_string(e.direction));
  if (!(std::isfinite(r.wheel_diameter_mm) && r.wheel_diameter_mm > 0))
    return Broken(key, error, "wheel.diameter_mm", "must be positive");
  if (!(r.wheel_eccentricity_mm >= 0 && r.wheel_eccentricity_mm < 0.1 * r.wheel_diameter_mm))
    return Broken(key, error, "wheel.eccentricity_mm", "must be 0 or more and under a tenth of the diameter");
  if (!(std::abs(r.wheel_eccentricity_phase_deg) <= 360.0))
    return Broken(key, error, "wheel.eccentricity_phase_deg", "must be an angle within +-360 degrees");
  if (!std::isfinite(r.offset_counts)) return Broken(key, error, "offset.counts", "must be a finite number");
  return true;
}

}  // namespace

bool IsValid(const Rig& r, bool with_areas, std::string* key, std::string* error) {
  if (r.has_wheel && !WheelIsValid(r, key, error)) return false;
  if (r.part && !(std::isfinite(r.part->radius_mm) && r.part->radius_mm >= 0.0))
    return Broken(key, error, "part.bed_radius_mm", "must be a positive radius in mm (or left out to be fitted)");
  if (!with_areas) return true;
  const ReferenceArea* areas[2] = {&r.reference_left, &r.reference_right};
  for (int i = 0; i < 2; ++i)
    if (!(std::isfinite(areas[i]->x_min_mm) && std::isfinite(areas[i]->x_max_mm) &&
          areas[i]->x_max_mm > areas[i]->x_min_mm))
      return Broken(key, error, i == 0 ? "sensor.reference_areas_mm[0]" : "sensor.reference_areas_mm[1]",
                    "is empty: the second x must be larger than the first");
  if (!(r.reference_left.x_max_mm < r.reference_right.x_min_mm))
    return Broken(key, error, "sensor.reference_areas_mm",
                  "the two reference areas overlap: the bead must lie in a gap between them");
  if (r.laser_origin && !(std::isfinite(r.laser_origin->x_mm) && std::isfinite(r.laser_origin->z_mm)))
    return Broken(key, error, "sensor.laser_origin_mm", "must be finite");
  return true;
}

}  // namespace bead
