// Volumetric flow in extrusion time (thesis 3.1.3, eq. 20: Q = v * A).
//
// For each profile: its unwrapped wheel position; the extrusion time t_e
// (extrusion_time.h); the surface speed v(t_e) from the log's encoder
// (unwrapped and repaired, Savitzky-Golay derivative of position, then a
// Hampel filter on the speed; times the rig's eccentricity factor for the
// wheel point that carried the material, Rig::SurfaceSpeedFactor); the area A (Hampel on the series, its sigma
// floored at the run's median area_sigma_mm2 so the edge-sampling sawtooth
// is not taken for outliers; optional Savitzky-Golay smoothing; a profile
// with no bead is area 0, one that could not be measured is a gap); the screw RPM at t_e from the log; and
// Q = v * A, with the corrected area where the occlusion stage gives one.
// The run's volume is the trapezoid integral of Q over extrusion time,
// bridging gaps linearly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/profile/bead_geometry.h"

namespace bead {

struct FlowOptions {
  // Savitzky-Golay window for the wheel speed, and its order. 0.04 s: a
  // quadratic over 0.1 s rounded off the corner where a stepped wheel
  // starts to change speed (against the twin's true speed, 1.1 % RMS off
  // within 0.3 s of a step, 12 % at the corner), and biased the offset from
  // the run by about +7 counts; over 0.04 s, 0.37 % (5.9 %), for 0.043 %
  // against 0.011 % of noise on a steady wheel (docs/explain.md).
  double speed_window_s = 0.04;
  int speed_order = 2;
  double speed_hampel_s = 0.05;  // Hampel half window on the speed
  int area_hampel_half = 5;      // Hampel half window on the area, profiles
  double hampel_nsigma = 3.0;
  // Floor on the area Hampel's sigma, mm^2; < 0: the batch takes the run's
  // median area_sigma_mm2, the streaming variant the running median so far.
  double area_sigma_floor_mm2 = -1.0;
  int area_smooth_window = 0;  // odd: Savitzky-Golay smoothing of the area (0: none)
  int area_smooth_order = 2;
  int max_fill = 10;  // gaps up to this many profiles are bridged
};

struct FlowSample {
  int64_t profile = 0;
  double t_s = 0.0;     // extrusion time (NaN: laid before the log began)
  int64_t encoder = 0;  // raw counter at extrusion time
  double surface_speed_mm_s = 0.0;
  double area_mm2 = 0.0;  // NaN: not measured
  double area_corrected_mm2 = 0.0;
  double occlusion_bias_mm2 = 0.0;        // area - corrected area
  double area_corrected_sigma_mm2 = 0.0;  // NaN when no occlusion stage ran
  double flow_mm3_s = 0.0;
  double flow_sigma_mm3_s = 0.0;  // v * area_corrected_sigma (the area's share)
  double screw_rpm = 0.0;
  bool valid = false;
};

struct FlowResult {
  std::vector<FlowSample> samples;  // one per profile, in profile order
  double total_volume_mm3 = 0.0;
  int area_outliers = 0;
  int speed_outliers = 0;
  int encoder_repairs = 0;
  // What is odd about the run, in words (the flow is still computed): the
  // profiles outside the log's time span, a wheel that never moved, no
  // bead anywhere, no sample with a flow at all.
  std::vector<std::string> warnings;
};

// What the run's warnings are made of, counted over the whole run (a
// streamed run counts them on the way).
struct FlowRunFacts {
  std::size_t profiles = 0, outside = 0, beads = 0, valid = 0;  // outside the log's span; valid geometry; with flow
  double log_first_s = 0, log_last_s = 0, profile_first_s = 0, profile_last_s = 0;
  double counts_min = 0, counts_max = 0;  // the repaired encoder positions' range
};
// FlowResult::warnings from them.
std::vector<std::string> FlowWarnings(const FlowRunFacts& facts);

// The Hampel sigma floor for the area series: the median area_sigma_mm2 of
// the valid profiles (0 when there are none).
double AreaSigmaFloor(const std::vector<BeadGeometry>& geometry);

// `corrected` and `corrected_sigma` (optional, same length as geometry):
// occlusion-corrected areas and their standard uncertainties.
FlowResult ComputeFlow(const Rig& rig, const ProfileBlock& profiles, const std::vector<BeadGeometry>& geometry,
                       const AcquisitionLog& log, const FlowOptions& options = {},
                       const std::vector<double>& corrected = {}, const std::vector<double>& corrected_sigma = {});

// The Savitzky-Golay window of the speed, in samples of spacing dt (odd).
int SpeedWindowSamples(const FlowOptions& options, double dt);

// Surface speed (mm/s) at each log sample.
std::vector<double> SurfaceSpeed(const Rig& rig, const std::vector<double>& t_s, const std::vector<double>& counts,
                                 const FlowOptions& options, int* outliers = nullptr);

}  // namespace bead
