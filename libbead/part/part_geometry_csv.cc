#include "libbead/part/part_geometry_csv.h"

#include <cmath>

#include "libbead/io/csv_reader.h"

namespace bead::part {

PartGeometryCsvWriter::PartGeometryCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "profile,t_s,layer,path_mm,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,"
                   "center_x_mm,offset_below_mm,shift_mm,shift_sigma_mm,shift_found,registration_rms_mm,noise_mm,"
                   "status\n";
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
  s += '\n';
  out_.stream() << s;
}

void PartGeometryCsvWriter::Commit() { out_.Commit(); }

}  // namespace bead::part
