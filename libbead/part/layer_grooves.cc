#include "libbead/part/layer_grooves.h"

#include <cmath>
#include <optional>
#include <utility>

namespace bead::part {
namespace {

// The row's area less the groove, with its sigma: the groove's, and the
// visible area's own sampling beside it: each of the bead's two edges a
// wall as high as the gain at its foot, placed anywhere within a point
// spacing, (spacing h_edge)^2 / 12 each. The layer below's walls under
// the bead are not counted: the area and the groove both stand on the
// same surface below there, and its error cancels in their difference.
// (Counting four walls as high as the bead, the 95 % interval covered
// 99.4 % of the material laid on the test walls, RMS of z 0.51; now 98.5 %,
// 0.63.) Written only where it means something: material left, known to
// better than half of it (else the ellipse did not find the bead's sides:
// the row keeps the area seen, and no correction). An ellipse placed at
// the silhouette has its ends where those walls are: its sigma holds them.
// Beside them, the area seen's own noise (AddedBead::AreaNoiseVar; left
// out, beads whose sides meet the surface, a groove of nothing, were given
// sigmas of 0.001 mm^2 against errors of 0.009: 28 % covered), and where
// the layer below steps between its two profiles around the row, where
// between them the step lies (BelowChange). (Left out, on a generator's
// contour whose beads of aspect 0.7 bulge through the corners, the rows
// where the layer below's bulge begins or ends were corrected 0.1-0.4
// mm^2 off at sigmas of 0.01, 10-39 of them; 30 of 2216 rows lay beyond 5
// sigmas, and a layer's intervals covered 90.8 %. Counted: 3, and 96.2 %.)
// And where the shape placed misses the row's seen top by more than a top
// may leave it (TopTolerance: the noise, and what any shape of the family
// leaves of a bead's top), its place is off by about that miss over the
// bead's width, and the area under its outline by the miss times the width:
// (top_rms^2 - tolerance^2) width^2. (Left out, single rows on the
// generator's walls with pass shifts of 0.8-1.2 mm, their tops 3-4
// tolerances off where their neighbours' were a third of one, were
// corrected 0.3-0.75 mm^2 off at sigmas of 0.05-0.11: 5-7 sigmas.)
double TopMissVar(const HiddenGroove& g, const PartGeometryRow& row) {
  const double tolerance = TopTolerance(row.bead.noise_mm, row.bead.height_mm);
  const double excess = g.top_rms_mm * g.top_rms_mm - tolerance * tolerance;
  return excess > 0.0 ? excess * row.bead.width_mm * row.bead.width_mm : 0.0;
}

void Apply(const HiddenGroove& g, double spacing, PartGeometryRow& row) {
  row.area_corrected_mm2 = row.area_corrected_sigma_mm2 = PartGeometryRow::kNaN;
  row.inside_cliff = false;
  row.outline_misfit = g.misfit;
  const double edges =
      g.at_silhouette
          ? 0.0
          : spacing * spacing *
                (row.bead.edge_left_mm * row.bead.edge_left_mm + row.bead.edge_right_mm * row.bead.edge_right_mm);
  const double corrected = row.bead.area_mm2 + g.seen_adjust_mm2 - g.hidden_mm2;
  const double sigma = std::sqrt(g.sigma_mm2 * g.sigma_mm2 + edges / 12.0 + row.bead.AreaNoiseVar(spacing) +
                                 row.below_change_var_mm4 + row.below_bend_var_mm4 + TopMissVar(g, row));
  if (g.ok && corrected > 0.0 && sigma < 0.5 * corrected)
    row.area_corrected_mm2 = corrected, row.area_corrected_sigma_mm2 = sigma, row.inside_cliff = g.inside_cliff;
}

}  // namespace

double TopOver(const HiddenGroove& g, const PartGeometryRow& row, double spacing_mm) {
  return TopMissTolerances(g.top_rms_mm, row.bead.noise_mm, row.bead.height_mm, g.aspect, spacing_mm);
}

HiddenGroove LayerGrooves::Estimate(const StoredProfile& p, const SurfaceGrid& under, const PartGeometryRow& row,
                                    const HiddenGroove* previous, const PooledShape* shape, double free_exponent,
                                    bool stadium_only) const {
  const double shift_sigma = std::isfinite(row.bead.shift_sigma_mm) ? row.bead.shift_sigma_mm : 0.0;
  const auto* carried = shape || !std::isnan(free_exponent) ? nullptr : Carried();
  if (std::isnan(free_exponent)) free_exponent = carried ? carried->second.exponent : 2.0;
  // A tamped bead's pool holds its height and ends' arcs in mm: at this
  // row's half-width.
  const std::optional<PooledShape> held = shape ? std::optional(shape->AtWidth(row.bead.width_mm)) : std::nullopt;
  return EstimateHiddenGroove(p.x_mm, p.z_mm, under, row.bead.shift_mm, shift_sigma, row.bead.noise_mm,
                              row.bead.center_x_mm, row.bead.width_mm, row.bead.height_mm, held ? &*held : nullptr,
                              previous, free_exponent, stadium_only);
}

void LayerGrooves::Record(const HiddenGroove& g, const PartGeometryRow& row, const StoredProfile& points, double top) {
  if (g.at_silhouette) ++at_walls_, ends_off_ += !g.shape_consistent;
  ++estimated_, walls_unsolved_ += g.walls_unsolved;
  const FamilyVote vote = FamilyVote::Of(g.family_log_ratio, row.bead.noise_mm, row.bead.height_mm);
  if (std::isfinite(vote.log_ratio)) family_votes_.push_back(vote);
  if (!g.ok || !g.shape_consistent) return;
  aspects_.push_back(g.aspect);
  if (std::isfinite(top)) tops_.push_back(top);
  if (g.at_silhouette)
    placed_.push_back({g.aspect, g.exponent, g.aspect_end_var, g.exponent_end_var, g.aspect_grid_var,
                       g.exponent_grid_var, g.left_end_mm, points.spacing_mm, g.end_mixed, g.aspect_mixed_var,
                       g.exponent_mixed_var, top, 0.5 * row.bead.width_mm, g.shape_a, g.pressed_half_mm, vote});
}

void LayerGrooves::ClearCounts() {
  aspects_.clear(), tops_.clear(), placed_.clear(), family_votes_.clear();
  at_walls_ = ends_off_ = estimated_ = walls_unsolved_ = 0;
}

void LayerGrooves::RetryAsStadiums() {
  if (stadium_only_ || placed_.size() >= kMinExponents || 2 * walls_unsolved_ <= estimated_ ||
      FamilyEvidence(family_votes_) <= 0)
    return;
  stadium_only_ = true;
  ClearCounts(), last_.reset();
  for (Waiting& w : waiting_)
    if (w.points) w.top_noise = Place(w.row, *w.points, *w.under);
}

double LayerGrooves::Place(PartGeometryRow& row, const StoredProfile& points, const SurfaceGrid& under) {
  const HiddenGroove g =
      Estimate(points, under, row, last_ ? &*last_ : nullptr, pooled_ ? &*pooled_ : nullptr, NAN, stadium_only_);
  if (g.ok) last_ = g;
  Apply(g, points.spacing_mm, row);
  const double top = TopOver(g, row, points.spacing_mm);
  if (!pooled_) Record(g, row, points, top);
  return top;
}

void LayerGrooves::Add(PartGeometryRow row, const StoredProfile* points, const SurfaceGrid* under, const Emit& emit) {
  if (row.layer != layer_) {
    Flush(emit);
    ClearCounts(), pooled_.reset(), last_.reset(), layer_ = row.layer, stadium_only_ = false;
  }
  const double top = points && under ? Place(row, *points, *under) : NAN;
  if (pooled_ && waiting_.empty()) return emit(row);
  waiting_.push_back({std::move(row), points && under ? std::optional(*points) : std::nullopt,
                      points && under ? std::optional(*under) : std::nullopt, top});
  if (!pooled_ && aspects_.size() >= kPoolProfiles && aspects_.size() % kLooseStep == 0) {
    RetryAsStadiums();
    const PooledShape pool = Pooled();
    // (What a footprint leaves, more rows do not shrink.)
    const bool loose = pool.aspect_rows_sigma > kLoosePool * pool.aspect && waiting_.size() < kMaxWaiting;
    if (!loose) Hold(pool);  // loose: more rows first
  }
  if (pooled_ || waiting_.size() >= kMaxWaiting) Flush(emit);
}

// The rows that waited, corrected with the pool where one is formed (or
// can be: kMinPoolProfiles rows), else with their own shapes: where those
// miss their tops by over kTopOffNoise times the noise (the pool's test,
// part/hidden_groove.h, on the row alone: nothing else judges it), not.
void LayerGrooves::Flush(const Emit& emit) {
  if (!pooled_) RetryAsStadiums();
  if (!pooled_ && aspects_.size() >= kMinPoolProfiles) Hold(Pooled());
  if (!pooled_) {
    for (Waiting& w : waiting_) {
      if (!std::isfinite(w.row.area_corrected_mm2)) continue;
      const bool top_off = w.top_noise > kTopOffNoise;
      if (!top_off && !EndsOff()) continue;
      w.row.area_corrected_mm2 = w.row.area_corrected_sigma_mm2 = PartGeometryRow::kNaN;
      w.row.outline_misfit = top_off ? OutlineMisfit::kTopOff : OutlineMisfit::kEndsOff;
    }
  } else {
    std::optional<HiddenGroove> previous;
    for (Waiting& w : waiting_) {
      if (!w.points) continue;
      const HiddenGroove g = Estimate(*w.points, *w.under, w.row, previous ? &*previous : nullptr, &*pooled_);
      if (g.ok) previous = g;
      Apply(g, w.points->spacing_mm, w.row);
    }
    if (previous) last_ = previous;
  }
  for (const Waiting& w : waiting_) emit(w.row);
  waiting_.clear();
}

const std::pair<int64_t, PooledShape>* LayerGrooves::Carried() const {
  for (auto it = pools_.rbegin(); it != pools_.rend(); ++it)
    if (it->first != layer_ && it->second.exponent_solved) return it->second.NotAnEllipse() ? &*it : nullptr;
  return nullptr;
}

void LayerGrooves::Hold(const PooledShape& pool) {
  pooled_ = pool;
  pools_.emplace_back(layer_, pool);
}

}  // namespace bead::part
