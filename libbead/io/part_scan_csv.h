// A part scan's CSV forms (format 1.1; docs/data-formats.md, "Part scan
// CSV forms"): its profiles in the long form with each profile's place,
//   profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm
// one row per point (an empty z_mm: no point), and its nozzle log,
//   t_s,layer,path_mm,screw_rpm[,head_speed_mm_s]
// `bead export` writes both; `bead import` reads the profiles as a vendor
// CSV (its columns named) and the log with --log; bead measure, flow,
// report and explain take the profiles CSV as they take the archive.
#pragma once

#include <memory>
#include <string>

#include "libbead/core/run_data.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"

namespace bead {

// Every `every`-th profile, written atomically.
void WritePartProfilesCsv(const std::string& path, const ProfileBlock& profiles, const PartPlaces& places,
                          std::size_t every = 1);
void WritePartLogCsv(const std::string& path, const AcquisitionLog& log);
// Throws naming the file and line where a row is not a part log's.
AcquisitionLog ReadPartLogCsv(const std::string& path);

// Whether `path` is a CSV whose header is the part profiles form's.
bool IsPartProfilesCsv(const std::string& path);
// The scan in a part profiles CSV: its profiles and their places (no log);
// throws naming the file and line where a row is wrong, or where a
// profile's rows disagree on its place.
RunArchive ReadPartProfilesCsv(const std::string& path);

// A part scan's profiles as a stream: an archive's window by window on
// `pool`, a part profiles CSV's read whole.
std::unique_ptr<ProfileStream> OpenPartProfiles(const std::string& path, WorkerPool& pool);

}  // namespace bead
