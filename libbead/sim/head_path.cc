#include "libbead/sim/head_path.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bead::sim {
namespace {

// The contour's corners as [begin, end) stretches of the path, mm: a
// rounded rectangle of sides a x b, corner radius R, the path starting in
// the middle of a side of length a and going round once.
std::vector<std::pair<double, double>> Corners(const PartTwinConfig& c) {
  const double a = c.contour_length_mm - 2.0 * c.corner_radius_mm, b = c.contour_width_mm - 2.0 * c.corner_radius_mm;
  const double arc = 0.5 * std::numbers::pi * c.corner_radius_mm;
  std::vector<std::pair<double, double>> out;
  double p = 0.5 * a;
  for (double side : {b, a, b, 0.0}) {
    out.emplace_back(p, p + arc);
    p += arc + side;
  }
  return out;
}

}  // namespace

HeadPath::HeadPath(const PartTwinConfig& c) : trail_(c.trail_mm), nominal_(c.head_speed_mm_s) {
  const bool contour = c.shape == PartTwinConfig::Shape::kContour;
  const double R = c.corner_radius_mm;
  length_ =
      contour ? 2.0 * (c.contour_length_mm + c.contour_width_mm - 4.0 * R) + 2.0 * std::numbers::pi * R : c.length_mm;
  const std::vector<std::pair<double, double>> corners = contour ? Corners(c) : decltype(Corners(c)){};
  // Through a corner: v^2 / R within the lateral limit; on the way to it
  // and from it: v^2 = v_c^2 + 2 a_t d, d the distance to the corner.
  const double v_corner = std::min(nominal_, std::sqrt(c.lateral_accel_mm_s2 * R));
  const std::size_t n = static_cast<std::size_t>((length_ + trail_) / step_) + 2;
  for (std::size_t k = 0; k < n; ++k) {
    const double p = static_cast<double>(k) * step_;
    double v = nominal_;
    for (const auto& [begin, end] : corners) {
      if (p > length_) break;
      const double d = p < begin ? begin - p : (p > end ? p - end : 0.0);
      v = std::min(v, std::sqrt(v_corner * v_corner + 2.0 * c.tangential_accel_mm_s2 * d));
    }
    speed_.push_back(v);
  }
  time_.assign(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) time_[k] = time_[k - 1] + step_ * 0.5 * (1.0 / speed_[k - 1] + 1.0 / speed_[k]);
}

double HeadPath::Sample(const std::vector<double>& v, double p) const {
  const double u = std::clamp(p / step_, 0.0, static_cast<double>(v.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(u), v.size() - 2);
  return v[k] + (u - static_cast<double>(k)) * (v[k + 1] - v[k]);
}

double HeadPath::SpeedAt(double p) const { return p > length_ + trail_ ? nominal_ : Sample(speed_, p); }

double HeadPath::TimeAt(double p) const {
  const double end = static_cast<double>(time_.size() - 1) * step_;
  return p > end ? time_.back() + (p - end) / nominal_ : Sample(time_, p);
}

double HeadPath::PathAt(double t) const {
  if (t >= time_.back()) return static_cast<double>(time_.size() - 1) * step_ + (t - time_.back()) * nominal_;
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(time_.begin(), time_.end(), t) - time_.begin());
  if (k == 0) return 0.0;
  const double w = (t - time_[k - 1]) / (time_[k] - time_[k - 1]);
  return (static_cast<double>(k - 1) + w) * step_;
}

}  // namespace bead::sim
