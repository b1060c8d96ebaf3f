#include "libbead/part/part_csv.h"

#include <cmath>

#include "libbead/io/csv_reader.h"

namespace bead::part {

PartGeometryCsvWriter::PartGeometryCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "profile,t_s,layer,path_mm,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,"
                   "center_x_mm,offset_below_mm,shift_mm,shift_sigma_mm,shift_found,registration_rms_mm,noise_mm,"
                   "status,area_corrected_sigma_mm2\n";
}

void PartGeometryCsvWriter::Append(const PartGeometryRow& r) {
  const AddedBead& b = r.bead;
  const bool ok = b.valid();
  std::string& s = line_;
  s.clear();
  auto number = [&s](double v) {
    AppendCsvNumber(s, v);
    s += ',';
  };
  auto whole = [&s](int64_t v) { s += std::to_string(v) + ','; };
  auto value = [&](double v) { ok ? number(v) : void(s += ','); };
  whole(r.profile);
  number(r.t_s);
  whole(r.layer);
  number(r.path_mm);
  value(b.area_mm2);
  value(b.width_mm);
  value(b.height_mm);
  value(r.area_corrected_mm2);
  s += ok ? "1," : "0,";
  value(b.center_x_mm);
  value(r.offset_below_mm);
  const bool registered = ok && std::isfinite(b.shift_sigma_mm);
  registered ? number(b.shift_mm) : void(s += ',');
  registered ? number(b.shift_sigma_mm) : void(s += ',');
  s += b.shift_constrained ? "1," : "0,";
  registered ? number(b.registration_rms_mm) : void(s += ',');
  number(b.noise_mm);
  s += AddedStatusName(b.status);
  s += ',';
  if (ok) AppendCsvNumber(s, r.area_corrected_sigma_mm2);
  s += '\n';
  out_.stream() << s;
}

void PartGeometryCsvWriter::Commit() { out_.Commit(); }

RoadsCsvWriter::RoadsCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "profile,bead,t_s,center_x_mm,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,layer,path_mm,"
                   "spacing_over_width,fit_rms_mm,status\n";
}

void RoadsCsvWriter::Append(const PartGeometryRow& r) {
  std::string& s = line_;
  for (std::size_t k = 0; k < r.roads.size(); ++k) {
    const Road& b = r.roads[k];
    s.clear();
    auto number = [&s](double v) {
      if (std::isfinite(v)) AppendCsvNumber(s, v);
      s += ',';
    };
    // A road cut by the field of view keeps its place, never its size.
    auto size = [&](double v) { b.valid() ? number(v) : void(s += ','); };
    s += std::to_string(r.profile) + ',' + std::to_string(k) + ',';
    number(r.t_s);
    number(b.center_x_mm);
    size(b.area_mm2);
    size(b.width_mm);
    size(b.height_mm);
    s += ',';  // area_corrected_mm2: the occlusion stage is not run on roads
    s += b.valid() ? "1," : "0,";
    s += std::to_string(r.layer) + ',';
    number(r.path_mm);
    size(b.spacing_over_width);
    number(b.fit_rms_mm);
    s += RoadStatusName(b.status);
    s += '\n';
    out_.stream() << s;
  }
}

void RoadsCsvWriter::Commit() { out_.Commit(); }

PartFlowCsvWriter::PartFlowCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "t_s,layer,path_mm,head_speed_mm_s,area_mm2,area_corrected_mm2,flow_mm3_s,screw_rpm,profile,valid\n";
}

void PartFlowCsvWriter::Append(const PartFlowRow& r) {
  std::string& s = line_;
  s.clear();
  auto number = [&s](double v) {
    AppendCsvNumber(s, v);
    s += ',';
  };
  number(r.t_s);
  s += std::to_string(r.layer) + ',';
  number(r.path_mm);
  number(r.head_speed_mm_s);
  number(r.area_mm2);
  number(r.area_corrected_mm2);
  number(r.flow_mm3_s);
  number(r.screw_rpm);
  s += std::to_string(r.profile) + (r.valid ? ",1\n" : ",0\n");
  out_.stream() << s;
}

void PartFlowCsvWriter::Commit() { out_.Commit(); }

}  // namespace bead::part
