// Writes a simulated run as DIR/run.h5, DIR/pins.h5, DIR/rig.yaml (the
// formats of docs/data-formats.md) and DIR/truth.h5:
//   /flow/{t_s, flow_mm3_s, area_mm2, surface_speed_mm_s, screw_rpm}   extrusion time, log rate
//   /profiles/{t_s, t_extruded_s, area_true_mm2, area_visible_mm2,
//              max_width_mm, contact_width_mm, height_mm, center_x_mm, dropped}  one per profile
//   /pins/{placement_error_mm, peak_counts}                             one per scan
//   /offset_counts, /rig_file_offset_counts, /total_volume_mm3          [1] each
// Every file is written atomically.
#pragma once

#include <string>

#include "libbead/sim/rig_simulator.h"

namespace bead::sim {

void WriteSimulatedRun(const std::string& dir, const SimulatedRun& run);

// Reads DIR/truth.h5 back (for tests and evaluations).
Truth ReadTruth(const std::string& path);

}  // namespace bead::sim
