#include "libbead/sim/sim_config.h"

namespace bead::sim {

SimConfig::SimConfig() {
  rig.name = "simulated-bcs";
  rig.encoder = {20480.0, 32, 1};  // 20480 counts/rev: 0.039 mm of surface per count (thesis 2.2: 0.038 mm)
  rig.wheel_diameter_mm = 254.762;
  rig.offset_counts = 3071.5;
  rig.reference_left = {-24.0, -12.0};
  rig.reference_right = {12.0, 24.0};
  rig.laser_origin = LaserOrigin{0.0, 95.0};
}

}  // namespace bead::sim
