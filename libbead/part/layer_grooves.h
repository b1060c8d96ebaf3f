// The groove a layer's beads hide under their overhangs (part/hidden_groove.h),
// taken off each row's area. One material, one process: the layer's first
// rows, each bead's shape its own (placed at its silhouette, or fitted),
// pool its beads' aspect b / a and exponent (part/superellipse.h), and every
// row of the layer is corrected with the shape held, the first ones too.
// One profile alone, where the bead's sides are seen poorly, can misplace
// its widest point (on the twin's contour, fitted from eight starts, one in
// ten of a layer's first rows was 4.5 % or more off, a few 8-10 %), so the
// rows measured before the pool is formed wait for it: kPoolProfiles rows
// with a shape of their own, more (every kLooseStep, up to kMaxWaiting)
// while the pooled aspect's sigma (less what a footprint leaves, which more
// rows do not shrink) exceeds kLoosePool of it; or, at a
// layer's end, the scan's end or kMaxWaiting rows, kMinPoolProfiles of them
// (a short layer is pooled on what it has); with fewer, the rows go out with
// their own shapes.
//
// The pool's error is shared by every row of the layer, so its size sets
// the layer's bias: on an independent generator's bead along a pipe (six
// seeds, upright and tilted ellipses), pooling 25 rows left the layer's
// corrected area -0.36..+1.02 % off over the run, 50 rows -0.25..+0.59 %,
// 100 rows -0.00..+0.54 % (the tilted bead's own +0.4 % then showing);
// each row pooled is estimated twice (free, then held): 50 costs the
// bench's 100-profile layers 11 % of their rate.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "libbead/part/hidden_groove.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

// A row's evidence between a bead's two families (part/superellipse.h):
// ln of the superellipse's residual variance over the stadium's
// (HiddenGroove::family_log_ratio), and the difference of the two, the
// superellipse's miss beyond the stadium's, over the bead's height squared
// (noise^2 (e^r - 1) / height^2: the noise estimated apart, from the
// profile's second differences).
struct FamilyVote {
  double log_ratio = NAN, excess_share = NAN;
  static FamilyVote Of(double log_ratio, double noise_mm, double height_mm) {
    return {log_ratio, noise_mm * noise_mm * std::expm1(log_ratio) / (height_mm * height_mm)};
  }
};
// The votes' verdict (the finite ones): +1 where their mean log ratio
// favours the stadium beyond kFamilyErrors of its standard error and the
// mean excess share beyond kFamilyMiss squared, -1 the superellipse
// alike, 0 neither (layer_pool.cc says why).
inline constexpr double kFamilyErrors = 3.0, kFamilyMiss = 0.002;
int FamilyEvidence(const std::vector<FamilyVote>& votes);

// A row's top's miss over its tolerance (OutlineMisfit::kTopOff), its
// points `spacing_mm` apart.
double TopOver(const HiddenGroove& g, const PartGeometryRow& row, double spacing_mm);

class LayerGrooves {
 public:
  using Emit = std::function<void(const PartGeometryRow&)>;
  static constexpr std::size_t kPoolProfiles = 50;
  static constexpr std::size_t kMinPoolProfiles = 10;
  static constexpr std::size_t kMaxWaiting = 4 * kPoolProfiles;
  // The exponent is solved over at least this many rows placed at their
  // walls (with 5, one independent layer whose shadowed walls let 6 rows be
  // placed, each misplaced alike, solved 2.15 +- 0.03 for an ellipse's 2).
  static constexpr std::size_t kMinExponents = 10;
  // The pool's error moves every row of the layer: on an independent
  // contour at 0.1 mm spacing and 20 um noise (six seeds) pools of 50 rows
  // held the aspect to 0.8-1.6 % and moved the layers' corrected areas by
  // about two thirds of their errors; gathered until 0.6 % (the first value
  // tried after 1 %, which changed little), the flow fits went from 73-82 %
  // to 78-83 %, the rows' median errors from 0.65-0.98 % to 0.52-0.82 %. The
  // twin's walls at 0.05 mm pool to 0.2-0.6 % on 50 rows: unchanged.
  static constexpr double kLoosePool = 0.006;
  static constexpr std::size_t kLooseStep = 25;

  // A measured row, in the scan's order, with its points and the surface
  // below them (nullptr: no groove to estimate: the bead not valid, no
  // surface below); rows go to `emit` in the same order, once corrected.
  void Add(PartGeometryRow row, const StoredProfile* points, const SurfaceGrid* under, const Emit& emit);
  // The rows still waiting, with their own fits (the scan's end).
  void Flush(const Emit& emit);
  // Each layer's pooled shape, in the order they were formed.
  const std::vector<std::pair<int64_t, PooledShape>>& pools() const { return pools_; }

  // A row placed at its silhouette: its shape, and for the pool's sigma
  // what its ends' cells leave.
  struct Placed {
    double aspect, exponent, aspect_end_var, exponent_end_var, aspect_grid_var, exponent_grid_var, left_end_mm,
        spacing_mm;
    bool end_mixed;
    double aspect_mixed_var, exponent_mixed_var;
    double top;      // its top's RMS over its tolerance (NaN: none)
    double half_mm;  // half its bead's width (part/added_bead.h), and its own half-width a
    double a_mm;
    double pressed_half_mm;  // HiddenGroove::pressed_half_mm
    FamilyVote family;
  };

 private:
  struct Waiting {
    PartGeometryRow row;
    std::optional<StoredProfile> points;
    std::optional<SurfaceGrid> under;
    double top_noise = NAN;  // its own shape's top RMS over its noise
  };
  // free_exponent: a free fit's (NaN: the carried one's, else 2);
  // stadium_only: part/hidden_groove.h.
  HiddenGroove Estimate(const StoredProfile& points, const SurfaceGrid& under, const PartGeometryRow& row,
                        const HiddenGroove* previous, const PooledShape* shape, double free_exponent = NAN,
                        bool stadium_only = false) const;
  // A row estimated before the pool, counted for it (its top's miss over
  // its tolerance: `top`).
  void Record(const HiddenGroove& g, const PartGeometryRow& row, const StoredProfile& points, double top);
  void ClearCounts();
  // A row estimated (with the layer's shape where pooled, the stadium's
  // family alone where RetryAsStadiums chose it), corrected, and counted
  // for the pool where none is yet; its top's miss (TopOver).
  double Place(PartGeometryRow& row, const StoredProfile& points, const SurfaceGrid& under);
  // Where most rows before the pool showed walls their tops solved no
  // shape over, too few were placed to solve the exponent, and the rows'
  // evidence favours the stadium (FamilyEvidence): the waiting rows
  // estimated again with the stadium's family alone, and counted anew
  // (once a layer). (At 30 um of noise on tamped beads 2 mm high, 392 of a
  // layer's first 400 rows left their walls unsolved, a superellipse
  // three times the bead's height taken for their tops; no layer of a
  // generator's wall was corrected. With the stadium alone: every row, 0.02
  // % over the run, 99.9 % covered, the flow fit 94 %.)
  void RetryAsStadiums();
  // The pool of the rows' shapes so far (layer_grooves.cc), and it held
  // for the layer's rows.
  PooledShape Pooled() const;
  void Hold(const PooledShape& pool);
  // The last earlier layer's pool whose exponent was solved, where that is
  // not an ellipse's (nullptr: none): a layer whose own rows do not solve
  // one holds it.
  const std::pair<int64_t, PooledShape>* Carried() const;
  // How the waiting rows' fitted aspects move with their exponent at p.
  double AspectByExponent(double p) const;
  // The median over up to kPoolProfiles waiting rows of their tops' RMS
  // over their tolerance, each estimated with `pool` held (NaN: none).
  double HeldTopNoise(PooledShape pool) const;

  int64_t layer_ = -1;
  std::vector<double> aspects_;
  std::vector<double> tops_;  // the same rows' tops' RMS over their noise
  std::vector<Placed> placed_;
  // The rows placed at their walls so far, and those whose top put an end
  // off its wall's cell (OutlineMisfit::kEndsOff); the layer's verdict.
  std::size_t at_walls_ = 0, ends_off_ = 0;
  // The rows estimated before the pool, and those whose walls showed but
  // whose tops solved no shape standing over them (PooledShape).
  std::size_t estimated_ = 0, walls_unsolved_ = 0;
  std::vector<FamilyVote> family_votes_;  // the rows', where they solved both families
  bool stadium_only_ = false;             // RetryAsStadiums done
  bool EndsOff() const { return at_walls_ >= kMinPoolProfiles && 2 * ends_off_ > at_walls_; }
  std::vector<std::pair<int64_t, PooledShape>> pools_;
  std::optional<PooledShape> pooled_;
  std::optional<HiddenGroove> last_;  // the layer's last fit: where the next starts
  std::vector<Waiting> waiting_;
};

}  // namespace bead::part
