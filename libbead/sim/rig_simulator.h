// The rig's digital twin: simulates a run of the bead characterisation
// system of the bead characterisation system thesis (large-scale AM extruder dynamics) (chapters 2-3) and what
// each instrument records, beside the truth.
//
// Chain: extruder command (V) -> screw RPM (transfer function, eq. 21)
// -> flow Q (mm^3/s, eq. 22) laid on the wheel surface moving at v, as a
// bead of area Q / v; the wheel carries it `offset` counts to the laser
// line, where the sensor's rays see its visible envelope. Encoders count
// wheel angle; a log records time, counter, screw RPM and commands.
#pragma once

#include <cstdint>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/io/run_archive.h"
#include "libbead/sim/sim_config.h"

namespace bead::sim {

struct FlowTruth {  // in extrusion time, at the log's rate
  std::vector<double> t_s, flow_mm3_s, area_mm2, surface_speed_mm_s, screw_rpm;
};

struct ProfileTruth {                    // one entry per recorded profile
  std::vector<double> t_s;               // true measurement time (the record may carry latency)
  std::vector<double> t_extruded_s;      // when the material under the laser left the nozzle (NaN: bare wheel)
  std::vector<double> area_true_mm2;     // the cross-section (0: no bead)
  std::vector<double> area_visible_mm2;  // what a noiseless, infinitely dense sensor integrates
  std::vector<double> max_width_mm, contact_width_mm, height_mm, center_x_mm;
  std::vector<int64_t> dropped;  // 1: the sensor dropped the whole profile
};

struct PinTruth {
  std::vector<double> placement_error_mm;  // along the travel, + toward the laser
  std::vector<double> peak_counts;  // wheel travel, in counts, from placement to where the pin centre meets the laser
};

struct Truth {
  FlowTruth flow;
  ProfileTruth profiles;
  PinTruth pins;
  double offset_counts = 0.0;  // the rig's true nozzle-to-laser offset
  double rig_file_offset_counts = 0.0;
  double total_volume_mm3 = 0.0;  // integral of the flow over the run
};

struct SimulatedRun {
  RunArchive run;
  PinScanArchive pins;
  Rig rig_file;  // what the rig file says (offset possibly off, see effects)
  Truth truth;
};

SimulatedRun Simulate(const SimConfig& config);

}  // namespace bead::sim
