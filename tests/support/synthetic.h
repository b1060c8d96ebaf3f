// Synthetic profiles for tests: a bead outline seen by the sensor model of
// libbead/sim, on a uniform or custom x grid, with the rig's default
// reference areas either side.
#pragma once

#include <random>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/core/profile_view.h"
#include "libbead/sim/sensor_model.h"

namespace bead::test {

inline const ReferenceArea kLeft{-24.0, -12.0};
inline const ReferenceArea kRight{12.0, 24.0};

struct Synthetic {
  std::vector<float> x, z;
  ProfileView view() const { return ProfileView{x, z, 0.0, 0}; }
  double spacing() const { return (x.back() - x.front()) / (x.size() - 1.0); }
};

inline std::vector<float> UniformGrid(int points, double x0 = -25.0, double x1 = 25.0) {
  std::vector<float> x(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i)
    x[static_cast<std::size_t>(i)] = static_cast<float>(x0 + (x1 - x0) * i / (points - 1));
  return x;
}

inline Synthetic Render(const sim::Outline& outline, const sim::SensorPose& pose, std::vector<float> grid,
                        const sim::SensorNoise& noise = {}, unsigned seed = 1) {
  Synthetic p;
  p.x = std::move(grid);
  p.z.resize(p.x.size());
  sim::RenderProfile(outline, pose, p.x, p.z);
  std::mt19937_64 rng(seed);
  sim::AddSensorNoise(p.z, noise, rng);
  return p;
}

}  // namespace bead::test
