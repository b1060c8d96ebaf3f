// Run and pin-scan archives (HDF5), as docs/data-formats.md defines
// them. Readers check every dataset's presence, type, shape and lengths,
// and that time is finite and increasing; they throw bead::Error naming
// the file and dataset. Writers write atomically.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "libbead/core/run_data.h"

namespace bead {

// A run on the wheel, or a part scan (format 1.1: `part` set, the root
// attribute kind = "part", no encoder: the profiles' encoder holds 0 and
// the attribute encoder = "absent" says so).
struct RunArchive {
  ProfileBlock profiles;
  std::optional<PartPlaces> part;
  std::optional<AcquisitionLog> log;
  std::map<std::string, std::string> attributes;  // root string attributes
};

// An archive written without encoder readings (`bead import` of an export
// without an encoder column, `bead frames`) holds encoder 0 and says so in
// the root attribute encoder = "absent" (an extension of the spec): what
// needs the wheel's motion refuses it instead of reading a standstill.
inline constexpr const char* kEncoderAttribute = "encoder";
inline constexpr const char* kEncoderAbsent = "absent";
inline bool EncoderAbsent(const RunArchive& run) {
  const auto it = run.attributes.find(kEncoderAttribute);
  return it != run.attributes.end() && it->second == kEncoderAbsent;
}

struct PinScan {
  int64_t start_encoder = 0;  // counter read with the pin under the nozzle centre
  ProfileBlock profiles;
};

struct PinScanArchive {
  std::vector<PinScan> scans;
  std::map<std::string, std::string> attributes;
};

RunArchive ReadRunArchive(const std::string& path);
// Whether the archive's root says kind = "part" (format 1.1), or a .csv
// is a part profiles CSV (io/part_scan_csv.h); false for anything else
// (the readers then say what the file is).
bool IsPartScan(const std::string& path);
// The same by the file's extension: a .h5's kind, a .csv's header; false
// for any other file (a .mat, a point cloud).
inline bool IsPartScanFile(const std::string& path) {
  return (path.ends_with(".h5") || path.ends_with(".csv")) && IsPartScan(path);
}
// A part scan (format 1.1), checked as a run archive is, and its places:
// lengths, finite values, layers from 0 that never fall (a layer's
// profiles together, the profiler trailing the nozzle).
RunArchive ReadPartScan(const std::string& path, bool with_profiles = true, bool with_log = true);
// A .csv: the part profiles CSV, read whole (profiles and places, no log).
// with_profiles = false: the log and root attributes only (the profiles
// are then read window by window, io/profile_stream.h); with_log = false:
// the log's datasets checked (presence, type, lengths) but not read (for
// what needs no wheel motion: an hour's log at 500 Hz is 70 MB).
RunArchive ReadRunArchive(const std::string& path, bool with_profiles, bool with_log = true);
void WriteRunArchive(const std::string& path, const RunArchive& run);
PinScanArchive ReadPinScanArchive(const std::string& path);
void WritePinScanArchive(const std::string& path, const PinScanArchive& pins);

// The shapes of a profiles group's datasets against each other, before
// their values are used: encoder [N] like t_s, z_mm [N, P], x_mm [P] or
// [N, P]. The dims are as HDF5 declares them (z_mm of rank 2).
void CheckProfileShapes(const std::string& file, const std::string& group, std::size_t profiles, std::size_t encoders,
                        const std::vector<std::size_t>& z_dims, const std::vector<std::size_t>& x_dims);

// Checks a block's internal consistency (lengths, finite increasing time,
// no infinite coordinates); `file` and `where` name it in the error.
void ValidateProfileBlock(const ProfileBlock& block, const std::string& file, const std::string& where);
// The same for profiles [first, first + N) of a dataset read in windows;
// previous_t: the time of profile first - 1 (NaN for the first window).
// Errors name the dataset's own row and column.
void ValidateProfileRows(const ProfileBlock& block, std::size_t first, double previous_t, const std::string& file,
                         const std::string& where);
void ValidateLog(const AcquisitionLog& log, const std::string& file, const std::string& where);
void ValidatePartPlaces(const PartPlaces& places, std::size_t profiles, const std::string& file,
                        const std::string& where);

}  // namespace bead
