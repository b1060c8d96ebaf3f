// A camera frame of the laser stripe as a profile: each column's stripe
// centre (stripe.h) mapped onto the laser plane (laser_plane.h), one point
// per image column, in column order; a column without a stripe (or whose
// centre maps to the plane's horizon) gives a point with x and z NaN (the
// profile stages skip it). The result feeds
// bead::ProfileProcessor like a profiler's own profile.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "libbead/vision/laser_plane.h"
#include "libbead/vision/stripe.h"

namespace bead::vision {

void FrameProfile(const cv::Mat& frame, const LaserPlaneMap& map, const StripeOptions& options,
                  std::vector<float>& x_mm, std::vector<float>& z_mm);

}  // namespace bead::vision
