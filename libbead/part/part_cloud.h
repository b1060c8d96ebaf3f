// A part scan's profiles as one point cloud in the bed frame (format 1.1):
// x = x + frame_x_mm across the path, s = path_mm along it, z = z +
// frame_z_mm above the bed, each point with its layer; io/point_cloud.h
// writes it as PLY or PCD. Layers stack at their heights: the part as
// printed, to open in CloudCompare or pcl_viewer.
#pragma once

#include "libbead/core/run_data.h"
#include "libbead/core/wheel_cloud.h"

namespace bead::part {

// Every `every`-th profile's finite points.
WheelCloud BuildPartCloud(const ProfileBlock& profiles, const PartPlaces& places, std::size_t every = 1);

}  // namespace bead::part
