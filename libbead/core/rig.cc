#include "libbead/core/rig.h"

#include <numbers>

namespace bead {

double Rig::MmPerCount() const {
  return std::numbers::pi * wheel_diameter_mm / encoder.counts_per_rev;
}

}  // namespace bead
