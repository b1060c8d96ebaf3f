#include "libbead/io/part_scan_csv.h"

#include <algorithm>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/part_datasets.h"
#include "libbead/io/run_archive.h"

namespace bead {

void WritePartProfilesCsv(const std::string& path, const ProfileBlock& b, const PartPlaces& p, std::size_t every) {
  AtomicFile out(path);
  auto& s = out.stream();
  s << "profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm\n";
  for (std::size_t i = 0; i < b.size(); i += std::max<std::size_t>(every, 1)) {
    const ProfileView v = b.view(i);
    for (std::size_t k = 0; k < b.points; ++k)
      s << i << ',' << CsvNumber(v.t_s) << ',' << p.layer[i] << ',' << CsvNumber(p.path_mm[i]) << ','
        << CsvNumber(p.frame_z_mm[i]) << ',' << CsvNumber(p.frame_x_mm[i]) << ',' << CsvNumber(v.x_mm[k]) << ','
        << CsvNumber(v.z_mm[k]) << '\n';
  }
  out.Commit();
}

void WritePartLogCsv(const std::string& path, const AcquisitionLog& log) {
  AtomicFile out(path);
  auto& s = out.stream();
  const bool speed = !log.head_speed_mm_s.empty();
  s << "t_s,layer,path_mm,screw_rpm" << (speed ? ",head_speed_mm_s" : "") << '\n';
  for (std::size_t i = 0; i < log.size(); ++i) {
    s << CsvNumber(log.t_s[i]) << ',' << log.layer[i] << ',' << CsvNumber(log.path_mm[i]) << ','
      << CsvNumber(log.screw_rpm[i]);
    if (speed) s << ',' << CsvNumber(log.head_speed_mm_s[i]);
    s << '\n';
  }
  out.Commit();
}

AcquisitionLog ReadPartLogCsv(const std::string& path) {
  CsvReader csv(path);
  const auto header = csv.Header({"t_s", "layer", "path_mm", "screw_rpm"}, "part scan log CSV");
  const bool speed = header.size() >= 5 && header[4] == "head_speed_mm_s";
  AcquisitionLog log;
  while (csv.Next()) {
    log.t_s.push_back(csv.Double(0, "t_s"));
    log.layer.push_back(csv.Int64(1, "layer"));
    log.path_mm.push_back(csv.Double(2, "path_mm"));
    log.screw_rpm.push_back(csv.Double(3, "screw_rpm"));
    if (speed) log.head_speed_mm_s.push_back(csv.Double(4, "head_speed_mm_s"));
  }
  if (log.size() == 0) throw Error(Located(path, "", "holds no log rows"));
  ValidateLog(log, path, "log");
  ValidatePartLog(log, path, "log");
  return log;
}

}  // namespace bead
