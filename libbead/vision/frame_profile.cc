#include "libbead/vision/frame_profile.h"

#include <cmath>
#include <limits>

#include "libbead/core/error.h"

namespace bead::vision {

void FrameProfile(const cv::Mat& frame, const SensorModel& sensor, StripeCentres& stripe, std::vector<float>& x_mm,
                  std::vector<float>& z_mm) {
  if (sensor.camera.Known() && frame.size() != sensor.camera.image_size)
    throw Error("frame of " + std::to_string(frame.cols) + " x " + std::to_string(frame.rows) +
                " px, the sensor's camera was calibrated for " + std::to_string(sensor.camera.image_size.width) +
                " x " + std::to_string(sensor.camera.image_size.height));
  FindStripe(frame, sensor.stripe, stripe);
  const std::size_t n = stripe.centres.size();
  std::vector<cv::Point2d> px(n);
  for (std::size_t k = 0; k < n; ++k) px[k] = stripe.Pixel(k);
  Undistort(sensor.camera, px);
  x_mm.assign(n, std::numeric_limits<float>::quiet_NaN());
  z_mm.assign(n, std::numeric_limits<float>::quiet_NaN());
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isnan(stripe.centres[k])) continue;
    const cv::Point2d p = ToLaserPlane(sensor.map, px[k]);
    if (!(std::isfinite(p.x) && std::isfinite(p.y))) continue;  // the plane's horizon: no point on it
    x_mm[k] = static_cast<float>(p.x);
    z_mm[k] = static_cast<float>(p.y);
  }
}

}  // namespace bead::vision
