// Rig: one rig placement, as described by the rig YAML file of
// shared/spec/data-formats.md. Plain data; the YAML reader lives in io/.
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

struct Rig {
  std::string name;
  EncoderSpec encoder;
  double wheel_diameter_mm = 0.0;
  double offset_counts = 0.0;  // encoder counts from the nozzle to the laser line
  ReferenceArea reference_left;   // the area at smaller x
  ReferenceArea reference_right;  // the area at larger x
  std::optional<LaserOrigin> laser_origin;

  // Surface travel per encoder count, mm.
  double MmPerCount() const;
};

}  // namespace bead
