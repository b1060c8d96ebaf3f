// Rig: one rig placement, as described by the rig YAML file of
// docs/data-formats.md. Plain data; the YAML reader lives in io/.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace bead {

// An x range of bare surface beside the bead, in sensor coordinates (mm).
struct ReferenceArea {
  double x_min_mm = 0.0;
  double x_max_mm = 0.0;
  bool Contains(double x_mm) const { return x_mm >= x_min_mm && x_mm <= x_max_mm; }
};

struct EncoderSpec {
  double counts_per_rev = 0.0;  // wheel encoder counts per wheel revolution
  int bits = 32;                // counter width; wraps modulo 2^bits; 0 = never wraps
  int direction = 1;            // +1: counts grow as the surface moves nozzle -> laser
};

struct LaserOrigin {
  double x_mm = 0.0;
  double z_mm = 0.0;
};

// The bed a part is printed on (format 1.1, the rig file's `part:`
// section): flat, or a cylinder whose axis runs along the toolpath (a
// first layer laid along a pipe).
struct PartBed {
  enum class Shape { kFlat, kCylinder };
  Shape shape = Shape::kFlat;
  double radius_mm = 0.0;  // cylinder: the radius; 0 = fitted from the bare surface
};

struct Rig {
  std::string name;
  // false: a part rig whose file has none of the wheel's sections (encoder,
  // wheel, offset); what needs the wheel refuses it.
  bool has_wheel = true;
  std::optional<PartBed> part;  // the rig file's part: section
  EncoderSpec encoder;
  double wheel_diameter_mm = 0.0;
  double offset_counts = 0.0;     // encoder counts from the nozzle to the laser line
  ReferenceArea reference_left;   // the area at smaller x
  ReferenceArea reference_right;  // the area at larger x
  std::optional<LaserOrigin> laser_origin;
  // The wheel's eccentricity as calibrated (`bead calibrate wheel`): the
  // wheel point under the laser at encoder angle theta (2 pi counts /
  // counts_per_rev, counts anchored to the raw counter) stands
  // e cos(theta - phase) off the mean radius. 0: a centred wheel.
  double wheel_eccentricity_mm = 0.0;
  double wheel_eccentricity_phase_deg = 0.0;

  // Surface travel per encoder count, mm.
  double MmPerCount() const;
  // The surface speed under the nozzle of the material that is at the
  // laser at unwrapped position `counts`, over the nominal omega R:
  // 1 + e cos(theta - phase) / R (the same wheel point carried it).
  double SurfaceSpeedFactor(double counts) const;
};

// The rules every rig obeys, whatever it came from (the rig file, the C
// interface, the simulator's config), in one place in the manner of Ceres'
// Solver::Options::IsValid: true, or false with `key` the rig file's key of
// the first rule broken ("encoder.bits") and `error` what it must be.
//  - encoder.counts_per_rev finite and > 0; encoder.bits 0 (never wraps) or
//    a counter width of 8 to 64; encoder.direction +1 or -1;
//  - wheel.diameter_mm finite and > 0; wheel.eccentricity_mm 0 or more and
//    under a tenth of the diameter, its phase within +-360 degrees;
//  - offset.counts finite;
//  - with `with_areas`: each reference area a finite, non-empty x range,
//    the left one ending before the right one begins (the bead lies in the
//    gap); a laser origin, when given, finite.
//  - a part rig without the wheel's sections skips their rules; a
//    cylinder's bed_radius_mm is 0 (fitted) or finite and > 0.
bool IsValid(const Rig& rig, bool with_areas, std::string* key, std::string* error);

}  // namespace bead
