// PartProfileProcessor: a part's profiles measured as they arrive, for
// acquisition software (as ProfileProcessor is the wheel's). A bead on the
// wheel is measured against the line through the bare surface either side;
// a part's against the surface it was laid on, the layer below at the same
// place along the path (part/surface_below.h). Both are the same
// measurement: the profile's gains over that surface go through the
// wheel's own kernel (profile/kernel.h) against the line z = 0, so the
// threshold, the gaps bridged, the feet and the sub-sample edges are the
// wheel's (no spike is bridged in the gains, and a foot stops where the gain
// rises again: the layer below's walls, part_profile_processor.cc). What a
// part adds is the surface below: kept from the layer before as its
// profiles pass (a layer or two in memory: the sensor's own rows where its
// points lie on one grid, part/sensor_rows.h; otherwise the general store),
// blended between its two profiles nearest along the path, and registered
// laterally (the passes' shift, never assumed zero): on a pass's first two
// profiles by the offline registration's wide search (part/registration.h,
// its hidden sigma kept for the pass), then by Gauss-Newton steps on the
// same truncated cost (the points whose gain is under the detection
// threshold, where the two surfaces agree) from the pass's last shift,
// settled by the same rules (no steps in a pass whose search found the
// layer below could hide a shift wider than the limit: none of its
// profiles can be constrained).
//
// What it leaves to the offline measurement (bead measure, part/
// measure_part.h): the groove a bead hides under its overhangs (the
// corrected area, a per-row fit of the bead's outline over the layer's
// pooled shape), the bead's centre at its top's middle (here: the area's
// centroid), the wall's wander, and the checks that the two scans' frames
// agree. Its area is the area seen, as the wheel's per-profile area is
// before the occlusion correction. It allocates while its first layers
// fill its buffers and on a pass's first two profiles (the wide search),
// not per profile after that.
//
//   bead::part::PartProfileProcessor processor(rig, {}, 800);
//   for (...) {
//     const auto& g = processor.Process(view, {layer, path_mm, frame_x_mm, frame_z_mm});
//     if (g.bead.status == bead::ProfileStatus::kValid && g.no_surface.empty()) ... g.bead.area_mm2 ...
//   }
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

#include "libbead/core/profile_view.h"
#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/part/grid_costs.h"
#include "libbead/part/sensor_rows.h"
#include "libbead/part/surface_below.h"
#include "libbead/profile/profile_processor.h"

namespace bead::part {

struct PartProfileOptions {
  ProfileOptions profile;  // layer 0's bed line and every layer's bead (threshold, spikes, gaps, feet)
  SurfaceBelowOptions below;
  // Gauss-Newton steps on the shift at most, per profile; the steps stop
  // when one moves it less than `shift_tolerance` point spacings.
  int shift_steps = 4;
  double shift_tolerance = 0.25;
  // A shift whose sigma exceeds this (or a point spacing, if larger: the
  // sigma's floor is spacing / sqrt 12) is not constrained (the layer below
  // has no slope where the surfaces agree): the pass's last is kept, mm.
  double max_shift_sigma_mm = 0.05;
};

// Where a profile lies on the part (format 1.1's /profiles/layer, path_mm,
// frame_x_mm, frame_z_mm).
struct PartPlace {
  int64_t layer = 0;
  double path_mm = 0.0, frame_x_mm = 0.0, frame_z_mm = 0.0;
  // Profile i's place in a scan's places.
  static PartPlace At(const PartPlaces& places, std::size_t i) {
    return {places.layer[i], places.path_mm[i], places.frame_x_mm[i], places.frame_z_mm[i]};
  }
};

struct PartProfileGeometry {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  PartPlace place;
  // In the bed frame: the bead's heights over the surface below (layer 0:
  // over the bed's reference line, the wheel's geometry moved by the frame);
  // its height the gain at the new surface's crest (as bead measure's),
  // its centre the area's centroid (bead measure's: the top's middle).
  // Its reference.residual_rms_mm: the noise the threshold was set on (a
  // gain's: the new point's and the surface below's).
  BeadGeometry bead;
  // Why there is no bead to look for, in words (empty: there is one): the
  // layer below not scanned there, or (layer 0) the bed's reference areas.
  std::string no_surface;
  // The layer below was moved by shift_mm (bed frame x) to agree with the
  // new profile outside its bead; its sigma from the points' noise and the
  // layer below's slope where they agree. Not constrained: the pass's last
  // shift kept (0 before one is found).
  double shift_mm = 0.0, shift_sigma_mm = kNaN;
  bool shift_constrained = false;
  int shift_steps = 0;  // Gauss-Newton steps taken
};

class PartProfileProcessor {
 public:
  explicit PartProfileProcessor(const Rig& rig, const PartProfileOptions& options = {}, std::size_t max_points = 2048);

  // One profile, in the order they were scanned (a layer needs the one
  // before it); the result stays valid until the next call.
  const PartProfileGeometry& Process(const ProfileView& view, const PartPlace& place);

 private:
  // A new layer: the pass's shift, noise and searches start again.
  void StartPass(int64_t layer);
  // A profile on the sensor's grid (x0 + k dx in its own frame), its
  // layer below read from the sensor's rows (part_profile_rows.cc).
  void OnSensorRows(const ProfileView& view, const PartPlace& place, double x0, double dx);
  void OverRows(const ProfileView& view, const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx);
  // The rows as the part kernel reads them at shift s, and the indices of
  // the new points inside every row, [begin, end).
  GridRows RowsAt(const SensorRows::Pair& below, double x0_bed, double dx, std::size_t n, double s,
                  std::ptrdiff_t& begin, std::ptrdiff_t& end) const;
  // below_z_ and heights_ at shift s (NaN outside every row), and the
  // registration's sums there (part_kernel.h local).
  GridSums GainsOnRows(const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx, std::size_t n,
                       double s, const GridShared& shared);
  // The pass's first profiles: the offline registration's wide search.
  void SearchWide(const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx, std::size_t n,
                  double noise);
  // Whether x is a uniform grid (part/sensor_rows.h UniformGrid), and its
  // start and spacing.
  bool OnTheGrid(std::span<const float> x, double& x0, double& dx);
  // A profile on no common grid: the rows kept so far handed to the
  // general store, which every later profile uses.
  void ToGeneralStore();
  // Layer 0: the wheel's geometry over the bed's line.
  void OnBed(const ProfileView& view);
  // The general store's path (points on any grid).
  void OverBelow(const SurfaceGrid& below);
  // The heights over the surface below moved by s (heights_), measured.
  void MeasureAt(const SurfaceGrid& below, double s, double noise);
  // Gauss-Newton steps on the shift from `s`; false where the layer below
  // does not constrain it.
  bool Register(const SurfaceGrid& below, double noise, double& s);
  // heights_ at the points x (z: the new surface there) through the
  // wheel's kernel, the gains' noise `noise`.
  void MeasureHeights(std::span<const float> x, std::span<const float> z, double noise);
  // The fewest points a profile is measured on (the wheel's, at least 3).
  std::size_t MinPoints() const;
  // A shift's sigma constrains it at most this (max_shift_sigma_mm, or a
  // point spacing if larger: the sigma's floor is spacing / sqrt 12).
  double ShiftSigmaLimit(double spacing) const;
  // Whether a profile of this pass can be constrained at all: not where the
  // pass's hidden sigma, a floor under every sigma in it, is over `limit`
  // (then no Gauss-Newton step is taken).
  bool PassMayMove(double limit) const { return !(pass_hidden_ > limit); }
  // The gains' detection threshold for one point's noise (as the offline
  // registration sets it: the wheel's rule, BeadOptions).
  double Tau(double noise) const;
  // The bead's places moved from the profiler's frame to the bed's.
  static void MoveByFrame(BeadGeometry& g, double frame_x);
  // The gain at the new surface's crest (the highest median of three of
  // its points between the bead's edges), as the offline height is.
  double GainAtCrest(std::span<const float> x, std::span<const float> z) const;

  Rig rig_;
  PartProfileOptions options_;
  ProfileProcessor bed_line_;
  ProfileWorkspace workspace_;
  const ProfileKernel* kernel_;
  SurfaceBelow below_;
  SensorRows rows_;
  bool lean_ = true;           // the sensor's rows in use (false: the general store, for good)
  std::vector<float> grid_x_;  // the last x found on a uniform grid, its start and spacing
  double grid_x0_ = 0.0, grid_dx_ = 0.0;
  int64_t layer_ = -1;
  const PartKernel* part_kernel_;
  PointsOnGrid on_grid_;
  StoredProfile bed_;
  std::vector<float> below_z_, heights_;
  PartProfileGeometry result_;
  // The pass's last constrained shift (NaN: none yet) and its gains'
  // noise (NaN: not yet estimated this pass).
  double pass_shift_ = kNaN, pass_noise_ = kNaN;
  // The pass's first search's hidden sigma (part/registration.h): a floor
  // under every shift's sigma in the pass.
  double pass_hidden_ = 0.0;
  // Where the last wide search pointed, and how many the pass has left.
  double pass_loose_ = 0.0;
  static constexpr int kWideSearches = 2;
  int wide_searches_ = kWideSearches;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace bead::part
