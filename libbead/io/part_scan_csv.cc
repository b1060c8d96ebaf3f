#include "libbead/io/part_scan_csv.h"

#include <algorithm>
#include <fstream>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/part_datasets.h"
#include "libbead/io/profile_block_builder.h"
#include "libbead/io/run_archive.h"

namespace bead {

namespace {

const std::vector<std::string> kPartProfileColumns = {"profile",    "t_s",        "layer", "path_mm",
                                                      "frame_z_mm", "frame_x_mm", "x_mm",  "z_mm"};

}  // namespace

void WritePartProfilesCsv(const std::string& path, const ProfileBlock& b, const PartPlaces& p, std::size_t every) {
  AtomicFile out(path);
  auto& s = out.stream();
  for (std::size_t c = 0; c < kPartProfileColumns.size(); ++c) s << (c ? "," : "") << kPartProfileColumns[c];
  s << '\n';
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

bool IsPartProfilesCsv(const std::string& path) {
  std::ifstream in(path);
  std::string header;
  if (!std::getline(in, header)) return false;
  if (!header.empty() && header.back() == '\r') header.pop_back();
  std::string want;
  for (const std::string& c : kPartProfileColumns) want += (want.empty() ? "" : ",") + c;
  return header.rfind(want, 0) == 0;
}

RunArchive ReadPartProfilesCsv(const std::string& path) {
  CsvReader csv(path);
  csv.Header(kPartProfileColumns, "part profiles CSV");
  ProfileBlockBuilder builder;
  PartPlaces places;
  while (csv.Next()) {
    const std::size_t before = builder.size();
    const int64_t layer = csv.Int64(2, "layer");
    const double path_mm = csv.Double(3, "path_mm"), frame_z = csv.Double(4, "frame_z_mm"),
                 frame_x = csv.Double(5, "frame_x_mm");
    builder.Add(csv, csv.Int64(0, "profile"), csv.Double(1, "t_s"), 0, csv.Coordinate(6, "x_mm"),
                csv.Coordinate(7, "z_mm"));
    if (builder.size() > before) {
      places.layer.push_back(layer), places.path_mm.push_back(path_mm);
      places.frame_z_mm.push_back(frame_z), places.frame_x_mm.push_back(frame_x);
    } else if (layer != places.layer.back() || path_mm != places.path_mm.back() ||
               frame_z != places.frame_z_mm.back() || frame_x != places.frame_x_mm.back()) {
      csv.Fail("a profile's rows disagree on its place (layer, path_mm, frame_z_mm, frame_x_mm): each profile has one");
    }
  }
  if (builder.empty()) throw Error(Located(path, "", "holds no profile rows"));
  RunArchive run;
  run.profiles = builder.Build(path, "profiles");
  ValidatePartPlaces(places, run.profiles.size(), path, "profiles");
  run.part = std::move(places);
  run.attributes = {{kKindAttribute, kKindPart}, {kEncoderAttribute, kEncoderAbsent}};
  return run;
}

std::unique_ptr<ProfileStream> OpenPartProfiles(const std::string& path, WorkerPool& pool) {
  if (path.ends_with(".csv")) return std::make_unique<ProfileStream>(path, ReadPartProfilesCsv(path).profiles);
  return std::make_unique<ProfileStream>(path, pool);
}

}  // namespace bead
