#include "libbead/part/measure_part.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "libbead/core/error.h"
#include "libbead/core/median.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/part/bed_arc.h"
#include "libbead/part/bed_stayed.h"
#include "libbead/part/layer_grooves.h"
#include "libbead/part/part_kernel.h"

namespace bead::part {
namespace {

// An eighth of the points' median spacing: the grid's own interpolation
// then adds little to the points' (the median: one stray point far off
// does not coarsen it).
double GridStep(const StoredProfile& p) { return p.x_mm.size() < 2 ? 0.01 : std::max(0.125 * p.spacing_mm, 1e-4); }

// A bed known as a height at every x of the profile's frame, sampled on a
// grid of `step` over the profile's span in the bed frame. at_points: the
// grid is the points' own (step: their spacing from the first), its
// variance 0 (a fitted line): the new points' gains and costs are then
// read on it as on a layer below (part/grid_costs.h).
template <class HeightAt>
std::optional<SurfaceGrid> SampledBed(const StoredProfile& p, double step, double frame_x, double frame_z,
                                      bool at_points, HeightAt height_at) {
  if (p.x_mm.size() < 2) return std::nullopt;
  SurfaceRow row;
  row.dx_mm = step;
  row.x0_mm = p.x_mm.front();
  const std::size_t n = GridPoints(p.x_mm.front(), p.x_mm.back(), row.dx_mm);
  if (n < 2) return std::nullopt;
  row.z_mm.resize(n);
  // (From locals, an int index: written through the row's own buffer, its
  // x0 and dx were read again for every value, and a 64-bit index turns
  // into a double one value at a time.)
  const double x0 = row.x0_mm, dx = row.dx_mm;
  float* z = row.z_mm.data();
  const auto count = static_cast<int>(n);
  for (int k = 0; k < count; ++k)
    z[k] = static_cast<float>(height_at(x0 + static_cast<double>(k) * dx - frame_x) + frame_z);
  if (at_points) row.at_points = true, row.variance.assign(n, 0.0f);
  return SurfaceGrid(std::move(row));
}

// Why the rig's reference areas hold no bare flat bed, if they do not
// (kValid where they do):
//  - kBeadInReferenceArea: a run of min_bead_points points there stands
//    over the line by the bead's threshold (the wheel's test,
//    profile/bead_geometry.cc, put to every run, not only the largest);
//  - kReferenceNotALine: the line leaves the areas' points over
//    kReferenceNoises times the profile's noise (ProfileNoiseMm of its
//    points in the bed frame) about it, and over the least bead threshold
//    (BeadOptions::min_threshold_mm): it is laid on a bead that fills an
//    area, or on a bed that is not flat there (a pipe). On a bare bed that
//    ratio is 0.8-1.2 (twin walls, contours and roads, a generator's walls
//    and roads; 4.5 on one profile whose noise sat at its 2 um floor); with
//    the tops of the outer ones of eight roads at 0.8 of their width in the
//    areas, 35-47 (0.35-0.47 mm): their bed line was laid on them, and every
//    road came out 83 % small, said nothing of. A bed rougher than a fine
//    sensor's noise (a textured sheet, 20-50 um about its line, under a
//    sensor of 1-2 um) stays under the threshold: nothing a bead's
//    threshold would see fills the areas, and it is measured on.
AddedStatus ReferenceAreas(const ProfileView& v, double noise_mm, const BeadGeometry& g, const Rig& rig,
                           const BeadOptions& bead) {
  const double not_a_line = std::max(kReferenceNoises * noise_mm, bead.min_threshold_mm);
  if (g.reference.residual_rms_mm > not_a_line) return AddedStatus::kReferenceNotALine;
  const int min_points = bead.min_bead_points;
  int run = 0;
  for (std::size_t j = 0; j < v.x_mm.size(); ++j) {
    const double x = v.x_mm[j];
    const bool in_area = rig.reference_left.Contains(x) || rig.reference_right.Contains(x);
    run = in_area && g.reference.HeightAt(x, v.z_mm[j]) > g.threshold_mm ? run + 1 : 0;
    if (run >= min_points) return AddedStatus::kBeadInReferenceArea;
  }
  return AddedStatus::kValid;
}

// The bed under layer 0 on a flat bed: the profile's reference line (a
// line: exact between any two of its values, so sampled at the points'
// own spacing); nullopt where none is found (`why`: kNoSurfaceBelow), or
// the reference areas hold no bare flat bed (`why`: ReferenceAreas').
std::optional<SurfaceGrid> BedLine(ProfileProcessor& processor, const Rig& rig, const BeadOptions& bead,
                                   const ProfileView& v, const StoredProfile& p, double noise_mm, double frame_x,
                                   double frame_z, AddedStatus& why) {
  const BeadGeometry& g = processor.Process(v);
  why = AddedStatus::kNoSurfaceBelow;
  if (!g.reference.ok) return std::nullopt;
  why = ReferenceAreas(v, noise_mm, g, rig, bead);
  if (why != AddedStatus::kValid) return std::nullopt;
  why = AddedStatus::kNoSurfaceBelow;  // where the grid below cannot be made
  const ReferenceLine line = g.reference;
  return SampledBed(p, std::max(p.spacing_mm, 1e-4), frame_x, frame_z, true,
                    [&line](double x) { return line.intercept_mm + line.slope * x; });
}

// The bed under layer 0 on a pipe (part: {bed: cylinder}): the arc through
// the profile's bare surface either side, in the bed frame.
std::optional<SurfaceGrid> BedArcGrid(const Rig& rig, const ProfileView& v, const StoredProfile& p, double frame_x,
                                      double frame_z) {
  const BedArc arc = FitBedArc(v.x_mm, v.z_mm, rig.reference_left, rig.reference_right, rig.part->radius_mm);
  if (!arc.ok) return std::nullopt;
  return SampledBed(p, GridStep(p), frame_x, frame_z, false, [&arc](double x) { return arc.At(x); });
}

// Each bead of the profile over the surface below, moved by `shift`.
std::vector<Road> RoadsOver(const StoredProfile& p, double noise_mm, const SurfaceGrid& under, double shift,
                            const RoadOptions& o) {
  std::vector<double> gain(p.x_mm.size());
  for (std::size_t j = 0; j < gain.size(); ++j) gain[j] = p.z_mm[j] - under.At(p.x_mm[j] - shift);
  return FindRoads(p.x_mm, gain, noise_mm, o);
}

class PartMeasurer {
 public:
  PartMeasurer(const Rig& rig, const MeasurePartOptions& o, std::size_t points)
      : rig_(rig), options_(o), processor_(rig.reference_left, rig.reference_right, o.bed, points), below_(o.below) {}

  // Measures the profile; its row (and any that waited for the layer's
  // pooled groove shape: part/layer_grooves.h) goes to `emit`.
  void Measure(const ProfileView& v, std::size_t i, const PartPlaces& places, const LayerGrooves::Emit& emit) {
    PartGeometryRow row;
    row.profile = static_cast<int64_t>(i);
    row.t_s = v.t_s;
    row.layer = places.layer[i];
    row.path_mm = places.path_mm[i];
    below_.BeginLayer(row.layer);
    StoredProfile mine = InBedFrame(v, row.path_mm, places.frame_x_mm[i], places.frame_z_mm[i], below_);
    const double noise = ProfileNoiseMm(mine.z_mm);  // (once: the bed's test, the bead, the roads)
    std::optional<SurfaceGrid> under;
    AddedStatus no_bed = AddedStatus::kNoSurfaceBelow;
    const bool pipe = rig_.part && rig_.part->shape == PartBed::Shape::kCylinder;
    if (row.layer == 0 && pipe)
      under = BedArcGrid(rig_, v, mine, places.frame_x_mm[i], places.frame_z_mm[i]);
    else if (row.layer == 0)
      under = BedLine(processor_, rig_, options_.bed.bead, v, mine, noise, places.frame_x_mm[i], places.frame_z_mm[i],
                      no_bed);
    else
      under = below_.At(row.path_mm, nullptr);
    if (!under) {
      row.bead.status = no_bed;  // on layer 0: no bed, or reference areas that hold no bare flat bed
    } else {
      const bool shift = row.layer > 0 && options_.register_layers;
      if (row.layer != warm_layer_) BeginPass(row.layer);
      double warm = RecentShift(), hidden = hidden_;
      const bool wide = shift && !std::isfinite(warm) && wide_searches_ > 0;
      wide_searches_ -= wide;
      if (!std::isfinite(warm) && !wide && loose_) warm = loose_->shift, hidden = loose_->hidden_sigma;
      row.bead = MeasureAddedBead(mine.x_mm, mine.z_mm, *under, shift, options_.added,
                                  std::isfinite(warm) ? &warm : nullptr, mine.spacing_mm, hidden, noise, wide);
      if (row.layer > 0) CheckBedStayed(mine, *under, places.frame_x_mm[i], rig_, options_.added, row.bead);
      if (row.bead.shift_constrained) KeepShift(row.bead.shift_mm), hidden_ = row.bead.shift_hidden_sigma_mm;
      const bool loose = shift && row.bead.valid() && !row.bead.shift_constrained;
      loose_ = loose ? std::optional(Loose{row.bead.shift_mm, row.bead.shift_hidden_sigma_mm}) : std::nullopt;
    }
    // Several beads over the surface below, at the shift the layer's
    // registration found (its truncated cost holds any number of beads).
    // (Not where the new surface lies under the one before it: the scans
    // are not where their frames say, and no bead is measured.)
    if (under && options_.several_beads && !row.bead.FramesDisagree())
      row.roads = RoadsOver(mine, noise, *under, row.bead.shift_mm, options_.roads);
    mine.center_x_mm = row.bead.valid() ? row.bead.center_x_mm : std::nan("");
    mine.area_mm2 = row.bead.valid() ? row.bead.area_mm2 : std::nan("");
    if (row.layer > 0 && row.bead.valid()) {
      const BelowChange change = below_.ChangeAt(row.path_mm);
      row.below_change_var_mm4 = change.Variance(), row.below_bend_var_mm4 = change.BendVariance();
    }
    if (row.layer > 0 && row.bead.valid() && (row.bead.shift_constrained || !options_.register_layers))
      row.offset_below_mm = row.bead.center_x_mm - (below_.CenterAt(row.path_mm) + row.bead.shift_mm);
    const bool groove = under && row.bead.valid() && options_.correct_hidden;
    grooves_.Add(std::move(row), groove ? &mine : nullptr, groove ? &*under : nullptr, emit);
    below_.Keep(std::move(mine));
  }
  void Flush(const LayerGrooves::Emit& emit) { grooves_.Flush(emit); }
  const LayerGrooves& grooves() const { return grooves_; }

 private:
  const Rig& rig_;
  MeasurePartOptions options_;
  ProfileProcessor processor_;
  SurfaceBelow below_;
  LayerGrooves grooves_;
  // The pass's last shifts found, to search from: their median (one
  // profile's shift off by a wall's sampling does not move the next's start).
  double RecentShift() const {
    if (recent_shifts_.empty()) return std::nan("");
    std::array<double, kRecentShifts> v{};
    std::copy(recent_shifts_.begin(), recent_shifts_.end(), v.begin());
    return MiddleInPlace(v.data(), recent_shifts_.size());
  }
  void KeepShift(double shift) {
    if (recent_shifts_.size() == kRecentShifts) recent_shifts_.erase(recent_shifts_.begin());
    recent_shifts_.push_back(shift);
  }
  void BeginPass(int64_t layer) {
    recent_shifts_.clear(), hidden_ = 0.0, warm_layer_ = layer, wide_searches_ = kWideSearches;
    loose_.reset();
  }
  static constexpr std::size_t kRecentShifts = 9;
  std::vector<double> recent_shifts_;
  double hidden_ = 0.0;  // the last shift kept's hidden sigma (part/registration.h), carried by a track
  // Where no shift of the pass is found yet, the profile before's least
  // (a bead covering the layer below: nothing of it shows, every shift in
  // the bracket costs the same) and its hidden sigma, to search about
  // first: its window's scan gives the same bracket where the bracket lies
  // inside it, and the whole range is searched where it does not
  // (part/registration.h). (Each such profile searched the whole range
  // afresh: a twin wall's first 24 profiles a layer, 480 costs each, 43 %
  // of its time.)
  struct Loose {
    double shift, hidden_sigma;
  };
  std::optional<Loose> loose_;
  // The pass's first registrations with no shift found yet look over the
  // whole span for a least beyond the first range (part/registration.h):
  // this many a pass (a layer whose shift is never found pays no more).
  static constexpr int kWideSearches = 2;
  int wide_searches_ = 0;
  int64_t warm_layer_ = -1;
};

}  // namespace

MeasurePartOptions PartOptionsFor(const ProfileOptions& profile) {
  MeasurePartOptions o;
  o.bed = profile;
  const BeadOptions& b = profile.bead;
  o.added.min_threshold_mm = o.roads.min_threshold_mm = b.min_threshold_mm;
  o.added.threshold_sigmas = o.roads.threshold_sigmas = b.threshold_sigmas;
  o.added.max_gap_mm = o.roads.max_gap_mm = b.max_gap_mm;
  o.roads.spike_mm = b.spike_mm;
  return o;
}

namespace {

// The median of `values` (a copy: the summary keeps its order), NaN where
// there are none.
double MedianOrNaN(std::vector<double> values) { return values.empty() ? LayerSummary::kNaN() : MiddleInPlace(values); }

}  // namespace

double LayerSummary::MedianUnder() const { return MedianOrNaN(under_mm); }
double LayerSummary::MedianBedOff() const { return MedianOrNaN(bed_off_mm); }
double LayerSummary::MedianShift() const { return MedianOrNaN(shifts_mm); }

namespace {

void Tally(std::vector<LayerSummary>& layers, const PartGeometryRow& r) {
  if (layers.empty() || layers.back().layer != r.layer) {
    layers.emplace_back();
    layers.back().layer = r.layer;
    layers.back().first_path_mm = r.path_mm;
  }
  LayerSummary& l = layers.back();
  ++l.profiles;
  l.first_path_mm = std::min(l.first_path_mm, r.path_mm);
  l.last_path_mm = std::max(l.last_path_mm, r.path_mm);
  l.no_surface_below += r.bead.status == AddedStatus::kNoSurfaceBelow;
  l.bead_in_reference += r.bead.status == AddedStatus::kBeadInReferenceArea;
  l.reference_not_a_line += r.bead.status == AddedStatus::kReferenceNotALine;
  if (r.bead.status == AddedStatus::kUnderSurfaceBelow) l.under_mm.push_back(r.bead.under_mm);
  if (r.bead.status == AddedStatus::kBedMoved) l.bed_off_mm.push_back(r.bead.bed_off_mm);
  if (!r.bead.valid()) return;
  ++l.valid;
  l.area_sum_mm2 += r.bead.area_mm2;
  if (std::isfinite(r.area_corrected_mm2)) {
    ++l.corrected;
    l.corrected_sum_mm2 += r.area_corrected_mm2;
    l.hidden_sum_mm2 += r.bead.area_mm2 - r.area_corrected_mm2;
    l.loose += r.area_corrected_sigma_mm2 > 0.1 * r.area_corrected_mm2;
    l.below_steps += r.below_change_var_mm4 > 0.0;
    l.inside_cliff += r.inside_cliff;
    l.below_step_sigma_mm2 = std::max(l.below_step_sigma_mm2, std::sqrt(r.below_change_var_mm4));
  } else {
    ++l.misfit[static_cast<std::size_t>(r.outline_misfit)];
  }
  if (r.bead.shift_constrained) ++l.shift_found, l.shifts_mm.push_back(r.bead.shift_mm);
}

}  // namespace

std::vector<LayerSummary> MeasurePart(ProfileStream& stream, const PartPlaces& places, const Rig& rig,
                                      const MeasurePartOptions& options,
                                      const std::function<void(const PartGeometryRow&)>& sink,
                                      const std::function<void(std::size_t)>& progress) {
  if (places.size() != stream.size())
    throw Error(Located(stream.name(), "/profiles/layer",
                        std::to_string(places.size()) + " places for " + std::to_string(stream.size()) + " profiles"));
  PartMeasurer measurer(rig, options, stream.points());
  std::vector<LayerSummary> layers;
  const LayerGrooves::Emit emit = [&](const PartGeometryRow& row) {
    Tally(layers, row);
    sink(row);
  };
  // Profiles in memory are read in place; an archive's window by window.
  const ProfileBlock* whole = stream.InMemory();
  ProfileBlock block;
  const std::size_t window = stream.WindowRows();
  for (std::size_t begin = 0; begin < stream.size(); begin += window) {
    const std::size_t count = std::min(window, stream.size() - begin);
    if (whole) {
      for (std::size_t k = begin; k < begin + count; ++k) measurer.Measure(whole->view(k), k, places, emit);
    } else {
      stream.Read(begin, count, block);
      for (std::size_t k = 0; k < count; ++k) measurer.Measure(block.view(k), begin + k, places, emit);
    }
    if (progress) progress(begin + count);
  }
  measurer.Flush(emit);
  for (const auto& [layer, shape] : measurer.grooves().pools())
    for (LayerSummary& l : layers)
      if (l.layer == layer) l.shape = shape;
  return layers;
}

std::vector<LayerSummary> MeasurePartFile(const std::string& path, const PartPlaces& places, const Rig& rig,
                                          const MeasurePartOptions& options, unsigned threads,
                                          const std::function<void(const PartGeometryRow&)>& sink,
                                          const std::function<void(std::size_t, std::size_t)>& progress) {
  WorkerPool pool(threads);
  const std::unique_ptr<ProfileStream> stream = OpenPartProfiles(path, pool);
  const std::size_t total = stream->size();
  return MeasurePart(*stream, places, rig, options, sink, [&](std::size_t done) {
    if (progress) progress(done, total);
  });
}

}  // namespace bead::part
