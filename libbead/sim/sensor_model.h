// What a laser line profiler reports of a bead on the wheel: for each
// sensor column, the first surface its ray meets (so shadows and undercuts
// are missed, as a real sensor misses them), then noise, quantisation,
// dropped points and reflection spikes.
//
// Frames: the sensor frame has x along the laser line and z toward the
// sensor. sensor_from_wheel rotates by the roll and then shifts:
//   x = cos(roll) s - sin(roll) h + x_offset,  z = sin(roll) s + cos(roll) h + z_offset.
// Rays either run along -z of the sensor frame (telecentric, one per entry
// of an x grid), or fan out from the laser origin toward (x_target, 0).
#pragma once

#include <optional>
#include <random>
#include <span>

#include "libbead/sim/outline.h"

namespace bead::sim {

struct SensorPose {
  double roll_rad = 0.0;
  double x_offset_mm = 0.0;
  double z_offset_mm = 0.0;  // runout moves this from profile to profile
};

struct SensorNoise {
  double z_sigma_mm = 0.0;    // Gaussian height noise
  double z_quantum_mm = 0.0;  // reported heights are multiples of this (0: none)
  double dropout_prob = 0.0;  // chance a point is missing (NaN)
  double spike_prob = 0.0;    // chance a point is a reflection spike
  double spike_mm = 0.0;      // spike height: uniform in [spike_mm / 2, spike_mm], either sign
};

// Noiseless envelope: z_out[j] is the height the ray at x_grid[j] meets,
// the outline or else the wheel surface.
void RenderProfile(const Outline& outline, const SensorPose& pose, std::span<const float> x_grid,
                   std::span<float> z_out);

// The laser fan's origin in the sensor frame.
struct Fan {
  double x_mm = 0.0;
  double z_mm = 95.0;
};

// Fan rays from `fan` toward (x_target[j], 0); each reports the first
// surface it meets, (x_out[j], z_out[j]) in the sensor frame.
void RenderProfileFan(const Outline& outline, const SensorPose& pose, const Fan& fan, std::span<const float> x_target,
                      std::span<float> x_out, std::span<float> z_out);

// Exact area between what the rays see first and the wheel surface: the
// bead plus the shadows the sensor cannot tell from it (what a noiseless
// sensor with infinitely many rays would integrate). No fan: parallel rays.
double VisibleArea(const Outline& outline, const SensorPose& pose, const std::optional<Fan>& fan);

void AddSensorNoise(std::span<float> z, const SensorNoise& noise, std::mt19937_64& rng);

}  // namespace bead::sim
