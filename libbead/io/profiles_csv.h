// The CSV interchange forms of docs/data-formats.md:
//  profiles (long form) profile,t_s,encoder,x_mm,z_mm
//  acquisition log      t_s,encoder,screw_rpm[,extruder_cmd_v,wheel_cmd_v]
//  pin scans            scan,start_encoder,profile,t_s,encoder,x_mm,z_mm
#pragma once

#include <string>

#include "libbead/io/run_archive.h"

namespace bead {

ProfileBlock ReadProfilesCsv(const std::string& path);
void WriteProfilesCsv(const std::string& path, const ProfileBlock& profiles);
AcquisitionLog ReadLogCsv(const std::string& path);
void WriteLogCsv(const std::string& path, const AcquisitionLog& log);
PinScanArchive ReadPinScansCsv(const std::string& path);

}  // namespace bead
