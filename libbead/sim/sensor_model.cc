#include "libbead/sim/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bead::sim {

void RenderProfile(const Outline& outline, const SensorPose& pose, std::span<const float> x_grid,
                   std::span<float> z_out) {
  const double c = std::cos(pose.roll_rad), sn = std::sin(pose.roll_rad);
  Outline sensor(outline.size());
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d& p = outline[i];
    sensor[i] = {c * p.x() - sn * p.y() + pose.x_offset_mm, sn * p.x() + c * p.y() + pose.z_offset_mm};
  }
  for (std::size_t j = 0; j < x_grid.size(); ++j) {
    const double x = x_grid[j];
    // The wheel surface h = 0: s = (x - x_offset) / cos, z = sin s + z_offset.
    double z = sn * (x - pose.x_offset_mm) / c + pose.z_offset_mm;
    for (std::size_t i = 0; i + 1 < sensor.size(); ++i) {
      const Eigen::Vector2d& p = sensor[i];
      const Eigen::Vector2d& q = sensor[i + 1];
      if (p.x() == q.x() || x < std::min(p.x(), q.x()) || x > std::max(p.x(), q.x())) continue;
      const double t = (x - p.x()) / (q.x() - p.x());
      z = std::max(z, p.y() + t * (q.y() - p.y()));
    }
    z_out[j] = static_cast<float>(z);
  }
}

void AddSensorNoise(std::span<float> z, const SensorNoise& noise, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (float& v : z) {
    double value = v;
    if (noise.z_sigma_mm > 0) value += noise.z_sigma_mm * gauss(rng);
    if (noise.z_quantum_mm > 0) value = noise.z_quantum_mm * std::round(value / noise.z_quantum_mm);
    if (noise.spike_prob > 0 && uni(rng) < noise.spike_prob) {
      const double magnitude = noise.spike_mm * (0.5 + 0.5 * uni(rng));
      value += uni(rng) < 0.5 ? magnitude : -magnitude;
    }
    if (noise.dropout_prob > 0 && uni(rng) < noise.dropout_prob) value = std::numeric_limits<double>::quiet_NaN();
    v = static_cast<float>(value);
  }
}

}  // namespace bead::sim
