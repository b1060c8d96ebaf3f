// The part scan's result CSVs of docs/data-formats.md (format 1.1).
//
// Geometry: the spec
// columns profile,t_s,layer,path_mm,area_mm2,width_mm,height_mm,
// area_corrected_mm2,valid first, then ours: center_x_mm, offset_below_mm,
// shift_mm, shift_sigma_mm, shift_found, registration_rms_mm, noise_mm,
// status. Values of an invalid profile are empty, its row kept with the
// status saying why; offset_below_mm is empty where the passes' shift was
// not found (shift_found = 0), area_corrected_mm2 where no occlusion model
// ran.
#pragma once

#include <string>

#include "libbead/io/atomic_file.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_flow.h"

namespace bead::part {

class PartGeometryCsvWriter {
 public:
  explicit PartGeometryCsvWriter(const std::string& path);
  void Append(const PartGeometryRow& row);
  void Commit();

 private:
  AtomicFile out_;
  std::string line_;
};

// Flow along the path: the spec columns t_s,layer,path_mm,head_speed_mm_s,
// area_mm2,area_corrected_mm2,flow_mm3_s,screw_rpm, then profile, valid.
// t_s is when the nozzle laid the place; an invalid row keeps its place
// and time with the values empty.
// Several beads in one profile (the spec's one row per bead found):
// profile,bead,t_s,center_x_mm,area_mm2,width_mm,height_mm,
// area_corrected_mm2,valid, then layer,path_mm,spacing_over_width,
// fit_rms_mm,status.
class RoadsCsvWriter {
 public:
  explicit RoadsCsvWriter(const std::string& path);
  void Append(const PartGeometryRow& row);
  void Commit();

 private:
  AtomicFile out_;
  std::string line_;
};

class PartFlowCsvWriter {
 public:
  explicit PartFlowCsvWriter(const std::string& path);
  void Append(const PartFlowRow& row);
  void Commit();

 private:
  AtomicFile out_;
  std::string line_;
};

}  // namespace bead::part
