// Geometry results CSV of docs/data-formats.md: the spec columns
// profile,t_s,encoder,area_mm2,width_mm,height_mm,area_corrected_mm2,valid
// first, then ours: center_x_mm, reference_rms_mm, reference_points,
// threshold_mm, dropped_points, status, area_sigma_mm2, occlusion_bias_mm2,
// area_corrected_sigma_mm2. Values of an invalid profile are empty; its
// row stays, with valid=0 and the status saying why. The occlusion columns
// are empty when no occlusion model was run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libbead/io/atomic_file.h"
#include "libbead/profile/geometry_row.h"

namespace bead {

// Rows appended one at a time (a streamed run), committed atomically.
class GeometryCsvWriter {
 public:
  explicit GeometryCsvWriter(const std::string& path);
  void Append(const GeometryRow& row);
  void Commit();

 private:
  AtomicFile out_;
  std::string line_;
};

void WriteGeometryCsv(const std::string& path, const std::vector<GeometryRow>& rows);

}  // namespace bead
