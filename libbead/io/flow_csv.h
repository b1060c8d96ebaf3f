// Flow results CSV of docs/data-formats.md: the spec columns
// t_s,encoder,surface_speed_mm_s,area_mm2,area_corrected_mm2,flow_mm3_s,screw_rpm
// (t_s: when the material left the nozzle; encoder: the raw counter then),
// then ours: profile, valid, occlusion_bias_mm2, area_corrected_sigma_mm2,
// flow_sigma_mm3_s (the last two empty without an occlusion stage). Rows whose extrusion time is unknown (laid
// before the log began) keep their row with empty values and valid=0.
#pragma once

#include <string>

#include "libbead/flow/flow.h"
#include "libbead/io/atomic_file.h"

namespace bead {

// Samples appended one at a time (a streamed run), committed atomically.
class FlowCsvWriter {
 public:
  explicit FlowCsvWriter(const std::string& path);
  void Append(const FlowSample& sample);
  void Commit();

 private:
  AtomicFile out_;
};

void WriteFlowCsv(const std::string& path, const FlowResult& flow);

}  // namespace bead
