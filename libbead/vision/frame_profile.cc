#include "libbead/vision/frame_profile.h"

#include <cmath>
#include <limits>

namespace bead::vision {

void FrameProfile(const cv::Mat& frame, const LaserPlaneMap& map, const StripeOptions& options,
                  std::vector<float>& x_mm, std::vector<float>& z_mm) {
  std::vector<float> rows;
  StripeCentres(frame, options, rows);
  x_mm.assign(rows.size(), std::numeric_limits<float>::quiet_NaN());
  z_mm.assign(rows.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t u = 0; u < rows.size(); ++u) {
    if (std::isnan(rows[u])) continue;
    const cv::Point2d p = ToLaserPlane(map, {static_cast<double>(u), rows[u]});
    if (!(std::isfinite(p.x) && std::isfinite(p.y))) continue;  // the plane's horizon: no point on it
    x_mm[u] = static_cast<float>(p.x);
    z_mm[u] = static_cast<float>(p.y);
  }
}

}  // namespace bead::vision
