#include "libbead/io/run_archive.h"

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <cstdlib>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/contained.h"
#include "libbead/io/hdf5_rows.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/part_datasets.h"

namespace bead {
namespace {

std::string Join(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

// `first`: the index of t[0] in the dataset; `previous`: the time before
// it (NaN: none), for a dataset read window by window.
void CheckTime(const std::vector<double>& t, const std::string& file, const std::string& dataset, std::size_t first = 0,
               double previous = std::nan("")) {
  auto at = [&](std::size_t i) { return dataset + "[" + std::to_string(first + i) + "]"; };
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i])) throw Error(Located(file, at(i), "time is not finite"));
    const double before = i > 0 ? t[i - 1] : previous;
    if ((i > 0 || !std::isnan(previous)) && !(t[i] > before))
      throw Error(Located(
          file, at(i), "time does not increase (" + std::to_string(before) + " then " + std::to_string(t[i]) + " s)"));
  }
}

// Reads <group>/t_s, encoder, x_mm, z_mm; a part scan has no encoder
// (`part`: 0 for each profile).
ProfileBlock ReadBlock(const h5::File& f, const std::string& group, bool part = false) {
  ProfileBlock b;
  const std::string t_name = Join(group, "t_s"), e_name = Join(group, "encoder");
  const std::string x_name = Join(group, "x_mm"), z_name = Join(group, "z_mm");
  b.t_s = f.ReadDouble(t_name, {1}).data;
  if (part)
    b.encoder.assign(b.t_s.size(), 0);
  else
    b.encoder = f.ReadInt64(e_name, {1}).data;
  auto x = f.ReadFloat(x_name, {1, 2});
  auto z = f.ReadFloat(z_name, {2});
  CheckProfileShapes(f.name(), group, b.t_s.size(), b.encoder.size(), {z.dims.begin(), z.dims.end()},
                     {x.dims.begin(), x.dims.end()});
  b.points = z.dims[1];
  b.shared_x = x.dims.size() == 1;
  b.x_mm = std::move(x.data);
  b.z_mm = std::move(z.data);
  ValidateProfileBlock(b, f.name(), group);
  return b;
}

void WriteBlock(h5::File& f, const std::string& group, const ProfileBlock& b, bool part = false) {
  const hsize_t n = b.size(), p = b.points;
  f.Write(Join(group, "t_s"), b.t_s, {n});
  if (!part) f.Write(Join(group, "encoder"), b.encoder, {n});
  if (b.shared_x)
    f.Write(Join(group, "x_mm"), b.x_mm, {p});
  else
    f.Write(Join(group, "x_mm"), b.x_mm, {n, p});
  f.Write(Join(group, "z_mm"), b.z_mm, {n, p});
}

// The log's datasets checked for presence, type, rank and lengths, their
// values not read (for a command that does not use the log: a damaged log
// is still reported, and an hour's log is not held for nothing).
void CheckLogShape(const h5::File& f, bool part) {
  std::vector<hsize_t> t, d;
  f.OpenDataset("/log/t_s", {1}, h5::Kind::kFloat, t);
  const struct {
    const char* name;
    h5::Kind kind;
    bool optional, wheel, part;
  } columns[] = {{"/log/encoder", h5::Kind::kInteger, false, true, false},
                 {"/log/screw_rpm", h5::Kind::kFloat, false, false, false},
                 {"/log/extruder_cmd_v", h5::Kind::kFloat, true, false, false},
                 {"/log/wheel_cmd_v", h5::Kind::kFloat, true, true, false},
                 {"/log/layer", h5::Kind::kInteger, false, false, true},
                 {"/log/path_mm", h5::Kind::kFloat, false, false, true},
                 {"/log/head_speed_mm_s", h5::Kind::kFloat, true, false, true}};
  for (const auto& c : columns) {
    if ((c.wheel && part) || (c.part && !part)) continue;
    if (c.optional && !f.Exists(c.name)) continue;
    f.OpenDataset(c.name, {1}, c.kind, d);
    CheckLength(d[0], t[0], f.name(), c.name, "/log/t_s");
  }
}

// The spec's own log datasets; every other float dataset [M] under /log is
// a recorded channel (docs/data-formats.md).
bool IsSpecLogDataset(const std::string& name) {
  return name == "t_s" || name == "encoder" || name == "screw_rpm" || name == "extruder_cmd_v" || name == "wheel_cmd_v";
}

// The other channels: float datasets of rank 1 and the log's length, their
// unit from a string attribute `unit` when there is one. Anything else
// under /log (a group, an integer counter, another length) is not a
// channel and is left alone.
std::vector<LogChannel> ReadChannels(const h5::File& f, std::size_t samples, bool part) {
  std::vector<LogChannel> out;
  for (const std::string& name : f.Members("/log")) {
    if (IsSpecLogDataset(name) || (part && IsPartLogDataset(name))) continue;
    const std::string path = "/log/" + name;
    std::vector<hsize_t> dims;
    try {
      f.OpenDataset(path, {1}, h5::Kind::kFloat, dims);
    } catch (const Error&) {
      continue;  // not a float vector
    }
    if (dims.empty() || dims[0] != samples) continue;
    LogChannel c;
    c.name = name;
    c.values = f.ReadDouble(path, {1}).data;
    const auto attributes = f.ReadStringAttributes(path);
    if (const auto it = attributes.find("unit"); it != attributes.end()) c.unit = it->second;
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

void CheckProfileShapes(const std::string& file, const std::string& group, std::size_t profiles, std::size_t encoders,
                        const std::vector<std::size_t>& z_dims, const std::vector<std::size_t>& x_dims) {
  const std::string t_name = Join(group, "t_s"), x_name = Join(group, "x_mm"), z_name = Join(group, "z_mm");
  CheckLength(encoders, profiles, file, Join(group, "encoder"), t_name);
  if (z_dims[0] != profiles)
    throw Error(Located(file, z_name,
                        "wrong shape: " + std::to_string(z_dims[0]) + " rows, but " + t_name + " has " +
                            std::to_string(profiles) + " profiles"));
  const std::size_t points = z_dims[1];
  if (x_dims.size() == 1 && x_dims[0] != points)
    throw Error(Located(file, x_name,
                        "wrong shape: " + std::to_string(x_dims[0]) + " points, but " + z_name + " has " +
                            std::to_string(points) + " per profile"));
  if (x_dims.size() == 2 && (x_dims[0] != profiles || x_dims[1] != points))
    throw Error(Located(file, x_name, "wrong shape: must be [N, P] like " + z_name + " or [P]"));
}

void ValidateProfileBlock(const ProfileBlock& b, const std::string& file, const std::string& where) {
  ValidateProfileRows(b, 0, std::nan(""), file, where);
}

void ValidateProfileRows(const ProfileBlock& b, std::size_t first, double previous_t, const std::string& file,
                         const std::string& where) {
  const std::string t_name = Join(where, "t_s");
  CheckLength(b.encoder.size(), b.size(), file, Join(where, "encoder"), t_name);
  CheckLength(b.z_mm.size(), b.size() * b.points, file, Join(where, "z_mm"), "N x P");
  CheckLength(b.x_mm.size(), b.shared_x ? b.points : b.size() * b.points, file, Join(where, "x_mm"),
              b.shared_x ? "P" : "N x P");
  CheckTime(b.t_s, file, t_name, first, previous_t);
  const std::size_t p = std::max<std::size_t>(b.points, 1);
  auto place = [&](const char* name, std::size_t i) {
    return Join(where, name) + "[" + std::to_string(first + i / p) + ", " + std::to_string(i % p) + "]";
  };
  // Shared x is checked with the first window only (it is the same for all).
  if (!b.shared_x || first == 0)
    for (std::size_t i = 0; i < b.x_mm.size(); ++i)
      if (std::isinf(b.x_mm[i]))
        throw Error(Located(file, b.shared_x ? Join(where, "x_mm") + "[" + std::to_string(i) + "]" : place("x_mm", i),
                            "infinite coordinate (an unmeasured point must be NaN)"));
  for (std::size_t i = 0; i < b.z_mm.size(); ++i)
    if (std::isinf(b.z_mm[i]))
      throw Error(Located(file, place("z_mm", i), "infinite height (an unmeasured point must be NaN)"));
}

void ValidateLog(const AcquisitionLog& log, const std::string& file, const std::string& where) {
  const std::string t_name = Join(where, "t_s");
  if (!log.part()) CheckLength(log.encoder.size(), log.size(), file, Join(where, "encoder"), t_name);
  CheckLength(log.screw_rpm.size(), log.size(), file, Join(where, "screw_rpm"), t_name);
  if (!log.extruder_cmd_v.empty())
    CheckLength(log.extruder_cmd_v.size(), log.size(), file, Join(where, "extruder_cmd_v"), t_name);
  if (!log.wheel_cmd_v.empty())
    CheckLength(log.wheel_cmd_v.size(), log.size(), file, Join(where, "wheel_cmd_v"), t_name);
  for (const LogChannel& c : log.channels) {
    if (c.name.empty() || IsSpecLogDataset(c.name) || (log.part() && IsPartLogDataset(c.name)) ||
        c.name.find('/') != std::string::npos)
      throw Error(
          Located(file, Join(where, c.name), "a recorded channel needs its own name (not a spec dataset's, no '/')"));
    CheckLength(c.values.size(), log.size(), file, Join(where, c.name), t_name);
  }
  CheckTime(log.t_s, file, t_name);
}

RunArchive ReadRunArchive(const std::string& path) { return ReadRunArchive(path, true); }

namespace {

// `part`: a part scan (format 1.1): no encoder, the places read and checked.
RunArchive ReadRunArchiveDirect(const std::string& path, bool with_profiles, bool with_log, bool part = false) {
  const h5::File f = h5::File::OpenRead(path);
  RunArchive run;
  if (with_profiles) run.profiles = ReadBlock(f, "/profiles", part);
  if (part) {
    std::vector<hsize_t> t;
    f.OpenDataset("/profiles/t_s", {1}, h5::Kind::kFloat, t);
    run.part = ReadPartPlaces(f, t[0]);
  }
  if (!with_log && f.Exists("/log")) CheckLogShape(f, part);
  if (with_log && f.Exists("/log")) {
    AcquisitionLog log;
    log.t_s = f.ReadDouble("/log/t_s", {1}).data;
    if (!part) log.encoder = f.ReadInt64("/log/encoder", {1}).data;
    log.screw_rpm = f.ReadDouble("/log/screw_rpm", {1}).data;
    if (f.Exists("/log/extruder_cmd_v")) log.extruder_cmd_v = f.ReadDouble("/log/extruder_cmd_v", {1}).data;
    if (!part && f.Exists("/log/wheel_cmd_v")) log.wheel_cmd_v = f.ReadDouble("/log/wheel_cmd_v", {1}).data;
    if (part) ReadPartLog(f, log);
    log.channels = ReadChannels(f, log.size(), part);
    ValidateLog(log, path, "/log");
    run.log = std::move(log);
  }
  run.attributes = f.ReadStringAttributes("/");
  if (part) run.attributes[kEncoderAttribute] = kEncoderAbsent;
  return run;
}

// The profile datasets' rows as the streamed reader reads them (the same
// RowReader, the same windows): all of them for a file up to 64 MB, whose
// whole reading then happens here first under the probe's bounds; the
// first and last window of a larger one.
void ProbeProfileRows(const h5::File& f, const std::string& path) {
  std::error_code ec;
  const auto file_bytes = std::filesystem::file_size(path, ec);
  const bool whole = !ec && file_bytes <= (std::uintmax_t{64} << 20);
  struct Dataset {
    const char* name;
    h5::Kind kind;
    hid_t mem;
  };
  for (const Dataset& d : {Dataset{"/profiles/t_s", h5::Kind::kFloat, H5T_NATIVE_DOUBLE},
                           Dataset{"/profiles/encoder", h5::Kind::kInteger, H5T_NATIVE_INT64},
                           Dataset{"/profiles/x_mm", h5::Kind::kFloat, H5T_NATIVE_FLOAT},
                           Dataset{"/profiles/z_mm", h5::Kind::kFloat, H5T_NATIVE_FLOAT}}) {
    if (!f.Exists(d.name)) continue;
    h5::RowReader rows(f, d.name, {1, 2}, d.kind, d.mem);
    const std::size_t n = rows.rows(), window = std::max<std::size_t>(rows.chunk_rows(), 256);
    std::vector<uint8_t> buffer(std::min(window, n) * rows.row_length() * H5Tget_size(d.mem));
    for (std::size_t begin = 0; begin < n; begin += window) {
      if (!whole && begin > 0 && begin + window < n) begin = n - std::min(window, n);
      rows.Read(begin, std::min(window, n - begin), buffer.data(), nullptr);
    }
  }
}

// A run archive holds /profiles; the other archives libbead reads are said
// by name when given in its place.
void CheckIsRunArchive(const h5::File& f, const std::string& path) {
  const std::map<std::string, std::string> root = f.ReadStringAttributes("/");
  if (const auto kind = root.find("kind"); kind != root.end() && kind->second == "part")
    throw Error(Located(path, "",
                        "is a part scan (root attribute kind = \"part\", format 1.1: beads on the layers of a "
                        "printed part): this command works on a run on the wheel; bead measure, flow, report, explain, "
                        "export and batch take a part scan"));
  if (f.Exists("/profiles")) return;
  if (f.Exists("/scans"))
    throw Error(Located(path, "",
                        "is a pin-scan archive (it holds /scans): this command takes a run archive "
                        "(/profiles and /log; bead simulate's run.h5)"));
}

// A part scan says so at its root; a run archive or a pin-scan archive
// given in its place is named.
void CheckIsPartScan(const h5::File& f, const std::string& path) {
  const std::map<std::string, std::string> root = f.ReadStringAttributes("/");
  if (const auto kind = root.find(kKindAttribute); kind != root.end() && kind->second == kKindPart) return;
  if (f.Exists("/scans")) throw Error(Located(path, "", "is a pin-scan archive (it holds /scans), not a part scan"));
  throw Error(Located(path, "",
                      "is not a part scan (its root has no attribute kind = \"part\"; a run archive on the wheel "
                      "is measured without part mode)"));
}

// What a reader of the archive touches in libhdf5: every profile dataset's
// header and rows (ProbeProfileRows), and the log with its channels.
void ProbeRunArchive(const std::string& path, bool with_log, bool part = false) {
  {
    const h5::File f = h5::File::OpenRead(path);
    if (part)
      CheckIsPartScan(f, path);
    else
      CheckIsRunArchive(f, path);
    ProbeProfileRows(f, path);
  }
  ReadRunArchiveDirect(path, false, with_log, part);
}

PinScanArchive ReadPinScanArchiveDirect(const std::string& path);

}  // namespace

RunArchive ReadRunArchive(const std::string& path, bool with_profiles, bool with_log) {
  ProbeContained(path, "HDF5", [&] { ProbeRunArchive(path, with_log); });
  return ReadRunArchiveDirect(path, with_profiles, with_log);
}

bool IsPartScan(const std::string& path) {
  if (path.ends_with(".csv")) return IsPartProfilesCsv(path);
  auto read = [&] {
    const h5::File f = h5::File::OpenRead(path);
    const auto root = f.ReadStringAttributes("/");
    const auto kind = root.find(kKindAttribute);
    return kind != root.end() && kind->second == kKindPart;
  };
  ProbeContained(path, "HDF5", [&] { read(); });  // in a contained child first
  return read();
}

RunArchive ReadPartScan(const std::string& path, bool with_profiles, bool with_log) {
  if (path.ends_with(".csv")) return ReadPartProfilesCsv(path);  // profiles and places; a CSV has no log
  ProbeContained(path, "HDF5", [&] { ProbeRunArchive(path, with_log, true); });
  return ReadRunArchiveDirect(path, with_profiles, with_log, true);
}

PinScanArchive ReadPinScanArchive(const std::string& path) {
  ProbeContained(path, "HDF5", [&] { ReadPinScanArchiveDirect(path); });
  return ReadPinScanArchiveDirect(path);
}

void WriteRunArchive(const std::string& path, const RunArchive& run) {
  ValidateProfileBlock(run.profiles, path, "/profiles");
  const bool part = run.part.has_value();
  if (part) ValidatePartPlaces(*run.part, run.profiles.size(), path, "/profiles");
  if (run.log) ValidateLog(*run.log, path, "/log");
  if (run.log && part != run.log->part())
    throw Error(Located(path, "/log", "a part scan's log holds layer and path_mm, a run's log the encoder"));
  AtomicFile out(path);
  {
    h5::File f = h5::File::Create(out.temp_path(), path);
    WriteBlock(f, "/profiles", run.profiles, part);
    if (part) WritePartPlaces(f, *run.part);
    if (run.log) {
      const hsize_t m = run.log->size();
      f.Write("/log/t_s", run.log->t_s, {m});
      if (part)
        WritePartLog(f, *run.log);
      else
        f.Write("/log/encoder", run.log->encoder, {m});
      f.Write("/log/screw_rpm", run.log->screw_rpm, {m});
      if (!run.log->extruder_cmd_v.empty()) f.Write("/log/extruder_cmd_v", run.log->extruder_cmd_v, {m});
      if (!run.log->wheel_cmd_v.empty()) f.Write("/log/wheel_cmd_v", run.log->wheel_cmd_v, {m});
      for (const LogChannel& c : run.log->channels) {
        f.Write("/log/" + c.name, c.values, {m});
        if (!c.unit.empty()) f.WriteStringAttribute("/log/" + c.name, "unit", c.unit);
      }
    }
    for (const auto& [key, value] : run.attributes)
      if (!(part && key == kEncoderAttribute)) f.WriteStringAttribute("/", key, value);
    if (part) f.WriteStringAttribute("/", kKindAttribute, kKindPart);
    f.Flush();
  }
  out.Commit();
}

namespace {

PinScanArchive ReadPinScanArchiveDirect(const std::string& path) {
  const h5::File f = h5::File::OpenRead(path);
  if (!f.Exists("/scans")) {
    if (f.Exists("/profiles"))
      throw Error(Located(path, "",
                          "is a run archive (it holds /profiles): this takes a pin-scan archive (/scans; "
                          "bead simulate's pins.h5)"));
    throw Error(Located(path, "/scans", "missing group: not a pin-scan archive"));
  }
  PinScanArchive pins;
  const std::vector<std::string> names = f.Members("/scans");
  std::vector<std::pair<long, std::string>> numbered;
  for (const std::string& name : names) {
    char* end = nullptr;
    const long k = std::strtol(name.c_str(), &end, 10);
    if (name.empty() || *end != '\0' || k < 0)
      throw Error(Located(path, "/scans/" + name, "scan groups must be named 0, 1, 2, ..."));
    numbered.emplace_back(k, name);
  }
  std::sort(numbered.begin(), numbered.end());
  if (numbered.empty()) throw Error(Located(path, "/scans", "holds no scans"));
  for (const auto& [k, name] : numbered) {
    const std::string group = "/scans/" + name;
    PinScan scan;
    scan.start_encoder = f.ReadInt64Attribute(group, "start_encoder");
    scan.profiles = ReadBlock(f, group + "/profiles");
    pins.scans.push_back(std::move(scan));
  }
  pins.attributes = f.ReadStringAttributes("/");
  return pins;
}

}  // namespace

void WritePinScanArchive(const std::string& path, const PinScanArchive& pins) {
  AtomicFile out(path);
  {
    h5::File f = h5::File::Create(out.temp_path(), path);
    for (std::size_t k = 0; k < pins.scans.size(); ++k) {
      const std::string group = "/scans/" + std::to_string(k);
      ValidateProfileBlock(pins.scans[k].profiles, path, group + "/profiles");
      f.CreateGroup(group);
      f.WriteInt64Attribute(group, "start_encoder", pins.scans[k].start_encoder);
      WriteBlock(f, group + "/profiles", pins.scans[k].profiles);
    }
    for (const auto& [key, value] : pins.attributes) f.WriteStringAttribute("/", key, value);
    f.Flush();
  }
  out.Commit();
}

}  // namespace bead
