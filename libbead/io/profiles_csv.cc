#include "libbead/io/profiles_csv.h"

#include <map>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/profile_block_builder.h"

namespace bead {
namespace {

// The spec's profile columns of the row `csv` reads, from column c on.
void AddProfileRow(ProfileBlockBuilder& builder, const CsvReader& csv, std::size_t c) {
  builder.Add(csv, csv.Int64(c, "profile"), csv.Double(c + 1, "t_s"), csv.Int64(c + 2, "encoder"),
              csv.Coordinate(c + 3, "x_mm"), csv.Coordinate(c + 4, "z_mm"));
}

const std::vector<std::string> kProfileColumns = {"profile", "t_s", "encoder", "x_mm", "z_mm"};

}  // namespace

ProfileBlock ReadProfilesCsv(const std::string& path) {
  CsvReader csv(path);
  csv.Header(kProfileColumns, "profiles CSV");
  ProfileBlockBuilder builder;
  while (csv.Next()) AddProfileRow(builder, csv, 0);
  if (builder.empty()) throw Error(Located(path, "", "holds no profile rows"));
  return builder.Build(path, "profiles");
}

void WriteProfilesCsv(const std::string& path, const ProfileBlock& b) {
  AtomicFile out(path);
  auto& s = out.stream();
  s << "profile,t_s,encoder,x_mm,z_mm\n";
  for (std::size_t i = 0; i < b.size(); ++i) {
    const ProfileView v = b.view(i);
    for (std::size_t k = 0; k < b.points; ++k)
      s << i << ',' << CsvNumber(v.t_s) << ',' << v.encoder << ',' << CsvNumber(v.x_mm[k]) << ','
        << CsvNumber(v.z_mm[k]) << '\n';
  }
  out.Commit();
}

AcquisitionLog ReadLogCsv(const std::string& path) {
  CsvReader csv(path);
  const auto header = csv.Header({"t_s", "encoder", "screw_rpm"}, "acquisition log CSV");
  const bool commands = header.size() >= 5 && header[3] == "extruder_cmd_v" && header[4] == "wheel_cmd_v";
  AcquisitionLog log;
  while (csv.Next()) {
    log.t_s.push_back(csv.Double(0, "t_s"));
    log.encoder.push_back(csv.Int64(1, "encoder"));
    log.screw_rpm.push_back(csv.Double(2, "screw_rpm"));
    if (commands) {
      log.extruder_cmd_v.push_back(csv.Double(3, "extruder_cmd_v"));
      log.wheel_cmd_v.push_back(csv.Double(4, "wheel_cmd_v"));
    }
  }
  if (log.size() == 0) throw Error(Located(path, "", "holds no log rows"));
  ValidateLog(log, path, "log");
  return log;
}

void WriteLogCsv(const std::string& path, const AcquisitionLog& log) {
  const bool commands = !log.extruder_cmd_v.empty() && !log.wheel_cmd_v.empty();
  AtomicFile out(path);
  auto& s = out.stream();
  s << "t_s,encoder,screw_rpm" << (commands ? ",extruder_cmd_v,wheel_cmd_v" : "") << '\n';
  for (std::size_t i = 0; i < log.size(); ++i) {
    s << CsvNumber(log.t_s[i]) << ',' << log.encoder[i] << ',' << CsvNumber(log.screw_rpm[i]);
    if (commands) s << ',' << CsvNumber(log.extruder_cmd_v[i]) << ',' << CsvNumber(log.wheel_cmd_v[i]);
    s << '\n';
  }
  out.Commit();
}

PinScanArchive ReadPinScansCsv(const std::string& path) {
  CsvReader csv(path);
  std::vector<std::string> columns = {"scan", "start_encoder"};
  columns.insert(columns.end(), kProfileColumns.begin(), kProfileColumns.end());
  csv.Header(columns, "pin-scan CSV");
  PinScanArchive pins;
  std::vector<ProfileBlockBuilder> builders;
  std::map<int64_t, std::size_t> index;
  int64_t last_scan = -1;
  while (csv.Next()) {
    const int64_t scan = csv.Int64(0, "scan");
    const int64_t start = csv.Int64(1, "start_encoder");
    if (builders.empty() || scan != last_scan) {
      if (index.count(scan)) csv.Fail("rows of scan " + std::to_string(scan) + " are not together");
      index[scan] = builders.size();
      builders.emplace_back();
      pins.scans.push_back({start, {}});
      last_scan = scan;
    } else if (start != pins.scans.back().start_encoder) {
      csv.Fail("scan " + std::to_string(scan) + " changes its start_encoder between rows");
    }
    AddProfileRow(builders.back(), csv, 2);
  }
  if (builders.empty()) throw Error(Located(path, "", "holds no pin-scan rows"));
  for (std::size_t k = 0; k < builders.size(); ++k)
    pins.scans[k].profiles = builders[k].Build(path, "scan " + std::to_string(k));
  return pins;
}

}  // namespace bead
