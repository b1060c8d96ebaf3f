// MeasurePart: a part scan's geometry (format 1.1), streamed. Each
// profile's bead is measured against the surface it was laid on
// (part/added_bead.h): layer 0 against the bed (the reference line over
// the rig's reference areas, as a bead on the wheel), every later layer
// against the layer below at the same place along the path
// (part/surface_below.h), registered laterally. The profiles are read
// window by window and measured in order (a layer needs the one before);
// memory holds one window and two layers' points, whatever the part's size.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/io/profile_stream.h"
#include "libbead/part/added_bead.h"
#include "libbead/part/groove_window.h"
#include "libbead/part/hidden_groove.h"
#include "libbead/part/roads.h"
#include "libbead/part/surface_below.h"
#include "libbead/profile/profile_processor.h"

namespace bead::part {

struct PartGeometryRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  int64_t profile = 0;
  double t_s = 0.0;
  int64_t layer = 0;
  double path_mm = 0.0;
  AddedBead bead;
  // The bead's centre less the centre of the bead below, both in the bed
  // frame (wall wander); NaN on layer 0 and where the registration was not
  // constrained (the passes' lateral shift unknown).
  double offset_below_mm = kNaN;
  // The area less the groove the bead hides under its overhangs
  // (part/hidden_groove.h), and its 1-sigma.
  double area_corrected_mm2 = kNaN, area_corrected_sigma_mm2 = kNaN;
  // The variance the layer below's blend along the path leaves in the
  // corrected area (part/surface_below.h BelowChange), mm^4; in its sigma.
  double below_change_var_mm4 = 0.0;
  double below_bend_var_mm4 = 0.0;  // BelowChange::BendVariance
  // Where there is none on a valid row because the bead's outline is not
  // one the model knows (part/hidden_groove.h), why.
  OutlineMisfit outline_misfit = OutlineMisfit::kNone;
  // HiddenGroove::inside_cliff, where corrected.
  bool inside_cliff = false;
  // MeasurePartOptions::several_beads: each bead of the profile, left to
  // right, over the same surface below, moved by bead.shift_mm.
  std::vector<Road> roads;
};

// On layer 0, the rig's reference areas are no line where their line
// leaves their points over this many times the profile's noise about it,
// and over the least bead threshold (AddedStatus::kReferenceNotALine;
// measure_part.cc says what it was set on).
inline constexpr double kReferenceNoises = 10.0;

struct MeasurePartOptions {
  ProfileOptions bed;  // the reference line of layer 0's bed
  AddedBeadOptions added;
  SurfaceBelowOptions below;
  // false: each layer subtracted from the one below as recorded (the
  // naive subtraction, for comparison); true: registered laterally.
  bool register_layers = true;
  // The groove an overhanging bead hides, estimated and taken off.
  bool correct_hidden = true;
  // Several beads in one profile (part/roads.h): roads of one layer, beads
  // welded side by side.
  bool several_beads = false;
  RoadOptions roads;
};

// The options a profile is measured with (the user's threshold, its noise
// sigmas, the longest dropout bridged, the spike rule), carried to every
// layer: layer 0's bed, the bead added over the layer below, and the roads.
// (Given only to the processor that fits layer 0's bed line, a part's
// --threshold-mm changed no layer's bead.)
MeasurePartOptions PartOptionsFor(const ProfileOptions& profile);

// A layer's rows in brief, for the tools' report.
struct LayerSummary {
  int64_t layer = 0;
  std::size_t profiles = 0, valid = 0, shift_found = 0, no_surface_below = 0;
  // On layer 0: AddedStatus::kBeadInReferenceArea, kReferenceNotALine.
  std::size_t bead_in_reference = 0, reference_not_a_line = 0;
  // AddedStatus::kUnderSurfaceBelow: how many, and the median of their
  // AddedBead::under_mm.
  std::vector<double> under_mm;
  double MedianUnder() const;
  // AddedStatus::kBedMoved: each row's AddedBead::bed_off_mm, their median.
  std::vector<double> bed_off_mm;
  double MedianBedOff() const;
  // The rows of both: the two scans not where their frames say.
  std::size_t FramesDisagree() const { return under_mm.size() + bed_off_mm.size(); }
  double area_sum_mm2 = 0.0;  // over the valid rows
  // Over the rows with a corrected area; `loose`: those whose corrected
  // area's sigma exceeds a tenth of it (the bead's sides not seen well
  // enough to place its widest point).
  std::size_t corrected = 0, loose = 0;
  // Of those, the rows where the layer below steps between its two profiles
  // around them (PartGeometryRow::below_change_var_mm4 above 0), and the
  // largest sigma that adds.
  std::size_t below_steps = 0;
  double below_step_sigma_mm2 = 0.0;
  // Of those, the rows placed at a wall inside a rise over a cliff
  // (PartGeometryRow::inside_cliff).
  std::size_t inside_cliff = 0;
  // The valid rows left without one because the bead's outline is not one
  // the model knows, by OutlineMisfit (kNone's count unused).
  std::size_t misfit[5] = {};
  std::size_t Misfits() const { return misfit[1] + misfit[2] + misfit[3] + misfit[4]; }
  double corrected_sum_mm2 = 0.0;
  // Over the same rows, the area seen less the corrected area: 0 where no
  // bead overhangs what it was laid on (nothing hidden).
  double hidden_sum_mm2 = 0.0;
  double MeanCorrected() const { return corrected ? corrected_sum_mm2 / static_cast<double>(corrected) : kNaN(); }
  double first_path_mm = 0.0, last_path_mm = 0.0;
  std::vector<double> shifts_mm;  // the shifts found (median: the pass's)
  // The layer's bead shape as its first rows pooled it (part/layer_grooves.h;
  // none where too few of them were corrected).
  std::optional<PooledShape> shape;
  double MeanArea() const { return valid ? area_sum_mm2 / static_cast<double>(valid) : kNaN(); }
  double MedianShift() const;
  static double kNaN() { return std::numeric_limits<double>::quiet_NaN(); }
};

// Calls `sink` with each profile's row, in the scan's order; `progress`
// (when given) with the profiles done so far. Returns each layer's brief.
std::vector<LayerSummary> MeasurePart(ProfileStream& stream, const PartPlaces& places, const Rig& rig,
                                      const MeasurePartOptions& options,
                                      const std::function<void(const PartGeometryRow&)>& sink,
                                      const std::function<void(std::size_t)>& progress = nullptr);

// The part scan at `path` measured as it streams, its profiles read on
// `threads` workers (0: every core); `progress` with the profiles done and
// their total.
std::vector<LayerSummary> MeasurePartFile(const std::string& path, const PartPlaces& places, const Rig& rig,
                                          const MeasurePartOptions& options, unsigned threads,
                                          const std::function<void(const PartGeometryRow&)>& sink,
                                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

}  // namespace bead::part
