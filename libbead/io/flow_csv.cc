#include "libbead/io/flow_csv.h"

#include <cmath>

#include "libbead/io/csv_reader.h"

namespace bead {

FlowCsvWriter::FlowCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "t_s,encoder,surface_speed_mm_s,area_mm2,area_corrected_mm2,flow_mm3_s,screw_rpm,profile,valid,"
                   "occlusion_bias_mm2,area_corrected_sigma_mm2,flow_sigma_mm3_s\n";
}

void FlowCsvWriter::Append(const FlowSample& f) {
  const bool known = std::isfinite(f.t_s);
  out_.stream() << CsvNumber(f.t_s) << ',' << (known ? std::to_string(f.encoder) : "") << ','
                << CsvNumber(f.surface_speed_mm_s) << ',' << CsvNumber(f.area_mm2) << ','
                << CsvNumber(f.area_corrected_mm2) << ',' << CsvNumber(f.flow_mm3_s) << ',' << CsvNumber(f.screw_rpm)
                << ',' << f.profile << ',' << (f.valid ? 1 : 0) << ',' << CsvNumber(f.occlusion_bias_mm2) << ','
                << CsvNumber(f.area_corrected_sigma_mm2) << ',' << CsvNumber(f.flow_sigma_mm3_s) << '\n';
}

void FlowCsvWriter::Commit() { out_.Commit(); }

void WriteFlowCsv(const std::string& path, const FlowResult& flow) {
  FlowCsvWriter out(path);
  for (const FlowSample& f : flow.samples) out.Append(f);
  out.Commit();
}

}  // namespace bead
