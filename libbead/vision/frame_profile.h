// A camera frame of the laser stripe as a profile: the stripe's centre on
// each image line across it (stripe.h), undistorted with the sensor's lens
// model when it has one, and mapped onto the laser plane (sensor.h): one
// point per line, in line order (per column when the stripe runs along
// the rows, per row when it runs down the columns). A line without a
// stripe (or whose centre maps to the plane's horizon) gives x and z NaN
// (the profile stages skip it). The result feeds bead::ProfileProcessor
// like a profiler's own profile.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "libbead/vision/sensor.h"

namespace bead::vision {

// stripe: the stripe's centres and counts, reused between calls; the
// axis used is stripe.axis (the sensor's, or the frame's when auto).
void FrameProfile(const cv::Mat& frame, const SensorModel& sensor, StripeCentres& stripe, std::vector<float>& x_mm,
                  std::vector<float>& z_mm);

}  // namespace bead::vision
