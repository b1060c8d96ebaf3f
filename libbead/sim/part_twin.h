// The twin prints a part: a straight wall, layer by layer (format 1.1 part
// scan), with its truth beside each profile.
//
// Each layer's bead is an ellipse (half-width a = width / 2, half-height
// aspect a; or a superellipse |u|^p + |v|^p = 1 of the config's exponent)
// laid on the surface the layers before left, sunk into it until the
// material it adds (the ellipse above the old surface) is the layer's
// area at that place; where it overhangs the bead below, the groove under
// its side is filled by nothing and hidden from a sensor looking down. The
// sensor sees the top envelope, max(old surface, ellipse top). The head's
// lateral position errs by a shift per pass (the registration's job: the
// frame's recorded x is 0), the bead wanders off the head's centre line
// per layer, the profiler trails the nozzle along the path, and the
// profiles of each layer fall at their own places along it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/io/run_archive.h"

namespace bead::sim {

struct PartTwinConfig {
  // A straight wall, or a closed contour with rounded corners (a rounded
  // rectangle contour_length_mm x contour_width_mm) that the head takes
  // slower while the extruder's flow goes on (the corner bulge).
  enum class Shape { kWall, kContour };
  Shape shape = Shape::kWall;
  double contour_length_mm = 100.0, contour_width_mm = 60.0, corner_radius_mm = 5.0;
  double lateral_accel_mm_s2 = 40.0;     // through a corner: v^2 / R at most this
  double tangential_accel_mm_s2 = 50.0;  // slowing into it and speeding out
  int layers = 6;
  double length_mm = 100.0;       // the wall's toolpath (a contour's is its perimeter)
  double head_speed_mm_s = 20.0;  // along the path, while printing (a contour's straights)
  double return_s = 2.0;          // travel back to the start between layers
  // A straight wall laid back and forth: every other layer (1, 3, ...)
  // from the far end back, the profiler trailing the nozzle the other way
  // and the log's path falling; the travel between layers a short move.
  bool alternate = false;
  double profile_spacing_mm = 0.5;
  double trail_mm = 30.0;               // the laser line behind the nozzle, along the path
  double width_mm = 6.0;                // the bead's ellipse, full width ...
  double aspect = 0.5;                  // ... and half-height over half-width ...
  double exponent = 2.0;                // ... and its superellipse's exponent (2: the ellipse)
  double area_mm2 = 12.0;               // the material a layer adds, mean (a contour: on its straights) ...
  double area_wave_mm2 = 2.0;           // ... a wave along the path of this amplitude ...
  double wave_period_mm = 40.0;         // ... and period
  double wander_sigma_mm = 0.3;         // the bead's centre off the head's line, per layer ...
  double wander_wave_mm = 0.1;          // ... and along the path, a sine of this amplitude ...
  double wander_wave_period_mm = 60.0;  // ... and period (its phase 1.3 rad a layer)
  double pass_shift_sigma_mm = 0.2;     // the head's lateral error, per pass
  // > 0: the profiler's frame moves sideways along the path by a known
  // amount (recorded as frame_x_mm), a sine of this amplitude and a period
  // of 23 mm: its points then lie on another grid in the bed frame at
  // each profile, mm.
  double frame_x_wave_mm = 0.0;
  double standoff_mm = 60.0;  // the profile frame's z = 0 this far above the layer's base
  double noise_mm = 0.01;
  // > 0: the points within this of each bead's right end, outside it, are
  // lost (NaN): a triangulation camera on the left, the bead hiding the
  // surface beside its right wall from it, mm.
  double shadow_mm = 0.0;
  double point_spacing_mm = 0.05;
  double field_half_mm = 20.0;  // the profile spans +-this in x
  double log_rate_hz = 100.0;
  // > 0: the wall is laid along the top of a pipe of this radius (its
  // axis along the path, its crest under the path's centre line), mm.
  double bed_radius_mm = 0.0;
  double displacement_mm3_per_rev = 100.0;  // screw rpm = 60 Q / this
  // > 1: one layer of this many roads laid side by side, left to right,
  // their centres this far apart, scanned after the layer (part_roads.yaml).
  int roads = 1;
  double road_spacing_mm = 5.0;
  uint64_t seed = 1;
};

// The truth of one profile, all in the bed frame.
struct PartTruthRow {
  int64_t layer = 0;
  double path_mm = 0.0;
  double area_mm2 = 0.0;          // the material the layer added
  double visible_area_mm2 = 0.0;  // the new top envelope over the old one: what the sensor can see was added
  double height_mm = 0.0;         // the envelope's gain at the crest
  double width_mm = 0.0;          // where the new envelope stands above the old
  double center_x_mm = 0.0;       // the bead's centre
  double offset_below_mm = 0.0;   // its centre less the one below's (0 on layer 0)
  double pass_shift_mm = 0.0;     // the head's lateral error in this pass
};

// A road of a layer of roads, at one profile.
struct PartRoadTruth {
  std::size_t profile = 0;
  int road = 0;                 // left to right, the laying order
  double area_mm2 = 0.0;        // its material
  double center_x_mm = 0.0;     // its ellipse's centre (the nozzle's line)
  double width_mm = 0.0;        // its ellipse's chord on the bed (its footprint, hidden parts included)
  double height_mm = 0.0;       // its ellipse's top over the bed
  double naive_area_mm2 = 0.0;  // what a vertical cut at the valleys gives it
};

struct PartTwin {
  RunArchive scan;                        // kind = "part"
  Rig rig;                                // no wheel; the bed's reference areas; part: flat
  std::vector<PartTruthRow> truth;        // one per profile, in the scan's order
  std::vector<PartRoadTruth> road_truth;  // a layer of roads: one per road and profile
  double path_length_mm = 0.0;            // a layer's toolpath (a contour's perimeter)
};

// What every part twin shares: the profiler's points across the part
// (field_half_mm either side, point_spacing_mm apart), and the rig (no
// wheel; the bed's reference areas the field's outer ReferenceWidthMm
// either side: 5 mm, or a quarter of field_half_mm where that is less, a
// glue bead's field of +-2 mm).
double ReferenceWidthMm(const PartTwinConfig& config);
void SetProfilerPoints(const PartTwinConfig& config, ProfileBlock& profiles);
Rig PartTwinRig(const PartTwinConfig& config, const std::string& name);

// The wall, the pipe, or (config.roads > 1) a layer of roads.
PartTwin SimulatePartWall(const PartTwinConfig& config);
PartTwin SimulateRoadLayer(const PartTwinConfig& config);

}  // namespace bead::sim
