// Point clouds in and out, through PCL (its own target, bead::cloud: the
// per-profile path never needs it).
//  - Out: a WheelCloud (core/wheel_cloud.h) as PLY (binary little-endian)
//    or PCD (binary compressed), chosen by the file's extension, written
//    atomically. Fields: x, y (= s along the wheel), z as float32 for
//    viewers (CloudCompare, pcl_viewer), and z_sensor (float32, the
//    sensor's own z), profile (uint32), t_s and encoder (float64: exact for
//    counters below 2^53) so that the run can come back in: its finite
//    points exactly, with z_sensor as z.
//  - In: a line scanner's PLY or PCD export as a run: the points of one
//    scan line share the value of the field the user names (`profile`),
//    and the lines are ordered by it; an organized cloud (rows x columns)
//    may leave it unnamed and give a profile per row. Any field type PCL
//    reads is taken (integers, float32, float64); a profile takes its first
//    point's time, and its points keep the file's order.
#pragma once

#include <string>

#include "libbead/core/wheel_cloud.h"
#include "libbead/io/import_columns.h"

namespace bead {

// Throws bead::Error naming the file when the extension is neither .ply
// nor .pcd, the cloud is empty, or PCL cannot write it.
void WritePointCloud(const std::string& path, const WheelCloud& cloud);

// Throws bead::Error naming the file and the field (and the fields there
// are) when a field is missing, a value is not finite where it must be,
// or the lines do not make a valid run (time not increasing, ...).
ImportedRun ReadPointCloud(const std::string& path, const ImportColumns& columns);

// True when `path` ends in .ply or .pcd (any case).
bool IsPointCloudPath(const std::string& path);

}  // namespace bead
