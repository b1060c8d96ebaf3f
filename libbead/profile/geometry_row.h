// GeometryRow: one profile's result as a run's later stages and files see
// it: where and when it was measured, its geometry, and the occlusion
// stage's correction (NaN where none ran). A plain, trivially copyable
// record (a streamed run spills rows to a scratch file and reads them back).
#pragma once

#include <cstdint>

#include "libbead/profile/bead_geometry.h"

namespace bead {

struct GeometryRow {
  int64_t profile = 0;
  double t_s = 0.0;
  int64_t encoder = 0;
  BeadGeometry geometry;
  double area_corrected_mm2 = BeadGeometry::kNaN;
  double occlusion_bias_mm2 = BeadGeometry::kNaN;
  double area_corrected_sigma_mm2 = BeadGeometry::kNaN;
};

}  // namespace bead
