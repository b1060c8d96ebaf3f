// A part scan's CSV forms (format 1.1; docs/data-formats.md, "Part scan
// CSV forms"): its profiles in the long form with each profile's place,
//   profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm
// one row per point (an empty z_mm: no point), and its nozzle log,
//   t_s,layer,path_mm,screw_rpm[,head_speed_mm_s]
// `bead export` writes both; `bead import` reads the profiles as a vendor
// CSV (its columns named) and the log with --log.
#pragma once

#include <string>

#include "libbead/core/run_data.h"

namespace bead {

// Every `every`-th profile, written atomically.
void WritePartProfilesCsv(const std::string& path, const ProfileBlock& profiles, const PartPlaces& places,
                          std::size_t every = 1);
void WritePartLogCsv(const std::string& path, const AcquisitionLog& log);
// Throws naming the file and line where a row is not a part log's.
AcquisitionLog ReadPartLogCsv(const std::string& path);

}  // namespace bead
