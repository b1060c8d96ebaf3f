// A layer's pool of its first rows' bead shapes (part/layer_grooves.h):
// the aspect, the exponent and its family, a tamped bead's height and
// ends' arcs, their sigmas, and an earlier layer's shape carried where the
// layer's own rows do not solve one.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include "libbead/core/median.h"
#include "libbead/part/layer_grooves.h"

namespace bead::part {

namespace {

// The median of v and its standard error: sqrt(pi / 2) sigma /
// sqrt(n), sigma from the median absolute deviation.
std::pair<double, double> MedianAndError(std::vector<double> v) {
  const double median = MiddleInPlace(v);
  for (double& a : v) a = std::abs(a - median);
  return {median, 1.2533 * 1.4826 * MiddleInPlace(v) / std::sqrt(static_cast<double>(v.size()))};
}

// The correlation of the rows' aspects and exponents (0 where either does
// not vary).
double ShapeCorrelation(const std::vector<LayerGrooves::Placed>& placed) {
  double ma = 0.0, mp = 0.0;
  for (const auto& p : placed) ma += p.aspect, mp += p.exponent;
  ma /= static_cast<double>(placed.size()), mp /= static_cast<double>(placed.size());
  double aa = 0.0, pp = 0.0, ap = 0.0;
  for (const auto& p : placed) {
    aa += (p.aspect - ma) * (p.aspect - ma), pp += (p.exponent - mp) * (p.exponent - mp);
    ap += (p.aspect - ma) * (p.exponent - mp);
  }
  return aa > 0.0 && pp > 0.0 ? std::clamp(ap / std::sqrt(aa * pp), -1.0, 1.0) : 0.0;
}

// The rows of one family (part/superellipse.h: a superellipse's or a
// stadium's; exponents of two families are not one quantity to take a
// median of): the family the rows' evidence between the two favours
// (FamilyEvidence), else the one most rows chose (a tie, the
// superellipse's). A row chooses the stadium only where the superellipse's
// residual is four of its sigmas over it (part/silhouette.cc:
// SolveEitherFamily), so where both follow a top closely, most rows may
// choose the superellipse whichever the bead is: on a generator's tamped
// wall at 40 mm/s (beads 4.8 mm wide, 2 mm high) 33-45 % of each layer's
// rows chose the stadium, though its residual was the lower in almost
// every row, and one layer's pool, a superellipse of aspect 1.38 and
// exponent 4.4, corrected it 13.6 % high.
std::vector<LayerGrooves::Placed> OfOneFamily(const std::vector<LayerGrooves::Placed>& placed) {
  std::size_t stadiums = 0;
  std::vector<FamilyVote> votes;
  for (const auto& p : placed) {
    stadiums += IsStadium(p.exponent);
    if (std::isfinite(p.family.log_ratio)) votes.push_back(p.family);
  }
  const int evidence = FamilyEvidence(votes);
  const bool stadium = evidence != 0 ? evidence > 0 : 2 * stadiums > placed.size();
  std::vector<LayerGrooves::Placed> out;
  for (const auto& p : placed)
    if (IsStadium(p.exponent) == stadium) out.push_back(p);
  return out;
}

// A stadium's pool in mm (PooledShape::half_height_mm): the rows' medians
// of b and of c a, each with its median's standard error, at least the
// floors the ends' places and the grid leave (floors: the aspect's and the
// exponent's, as the pool's), beside what a footprint leaves (spots: the
// same), both at the rows' median half-width; and the median of half the
// width measured less a (PooledShape::width_excess_mm), a being the
// half-width between the ends the top placed (Silhouette::shape_a: the
// aspect's and exponent's own, not the cells' middles'). b: where most
// rows' beads lie on a flat (HiddenGroove::pressed_half_mm), half their
// tops' height over it, its sigma at least half of what any shape leaves
// on a top, a share kTopShapeHeights of the height (part/hidden_groove.h:
// the tops are read through the shape placed on them, the same in every
// row; on 51 layers of a generator's walls, 0.05-0.2 mm spacing, the
// pools lay within 0.0007 mm of 1 mm, up to 4.7 of their standard errors
// of 0.00005-0.0006 off); else aspect times a.
// (The aspects' own spread is not the error here: a tamped bead's aspect
// follows its width along the path, through the corners' bulges. On a
// generator's tamped walls at 0.05 and 0.1 mm spacing, c a lies within 1.2
// of its sigma of the generator's 1 mm; at 0.2 mm, four points on each
// arc, -0.5 to +1.9 % off at up to 3.7 sigmas on 12 layers: left so, its share
// of the groove under a thousandth of the area.)
void PoolTamped(const std::vector<LayerGrooves::Placed>& placed, const std::array<double, 2>& floors,
                const std::array<double, 2>& spots, PooledShape& pool) {
  std::vector<double> b, pressed, corner, half, excess;
  for (const auto& p : placed) {
    b.push_back(p.aspect * p.a_mm), corner.push_back(-p.exponent * p.a_mm), half.push_back(p.a_mm);
    excess.push_back(p.half_mm - p.a_mm);
    if (std::isfinite(p.pressed_half_mm)) pressed.push_back(p.pressed_half_mm);
  }
  const double a = MedianAndError(half).first;
  const auto [corner_mm, corner_se] = MedianAndError(corner);
  pool.corner_mm = corner_mm;
  if (2 * pressed.size() > placed.size()) {
    const auto [b_mm, b_se] = MedianAndError(pressed);
    pool.half_height_mm = b_mm, pool.half_height_sigma_mm = std::hypot(b_se, kTopShapeHeights * b_mm);
  } else {
    const auto [b_mm, b_se] = MedianAndError(b);
    pool.half_height_mm = b_mm;
    pool.half_height_sigma_mm = std::hypot(std::max(b_se, floors[0] * a), spots[0] * a);
  }
  pool.corner_sigma_mm = std::hypot(std::max(corner_se, floors[1] * a), spots[1] * a);
  pool.width_excess_mm = MedianAndError(excess).first;
}

}  // namespace

// Sure: the mean log ratio beyond three of its standard errors. Large: the
// one family's top misses by more than kFamilyMiss of the bead's height
// beyond the other's (root mean excess share), which tells a shape apart
// from what both families' grids leave on one they both hold. Over a
// generator's layers (2 mm beads): tamped beads at 10 and 30 um of noise,
// 0.31-0.62 % (the log ratios 0.12-0.90: at 30 um a miss is a smaller share
// of the noise), pressed ellipses (in both families) 0.07-0.11 %.
int FamilyEvidence(const std::vector<FamilyVote>& votes) {
  std::vector<const FamilyVote*> finite;
  for (const FamilyVote& v : votes)
    if (std::isfinite(v.log_ratio) && std::isfinite(v.excess_share)) finite.push_back(&v);
  if (finite.size() < 2) return 0;
  const auto n = static_cast<double>(finite.size());
  double mean = 0.0, sq = 0.0, excess = 0.0;
  for (const FamilyVote* v : finite) mean += v->log_ratio / n, excess += v->excess_share / n;
  for (const FamilyVote* v : finite) sq += (v->log_ratio - mean) * (v->log_ratio - mean);
  const double error = std::sqrt(sq / (n - 1.0) / n);
  const int way = mean > 0.0 ? 1 : -1;
  const bool sure = std::abs(mean) > kFamilyErrors * error, large = way * excess > kFamilyMiss * kFamilyMiss;
  return sure && large ? way : 0;
}

// The layer's first rows' own shapes, then their pool, held: the aspect
// over every row, the exponent over those placed at their silhouette (a
// fit's is an ellipse's by assumption, not measured; with fewer than
// kMinExponents placed, the ellipse's is held; a row whose top disagrees
// with its walls' cells, none of its shape). (Each row's aspect solved
// again at the pooled exponent, its pool's sigma was a third as wide, and
// the walls' intervals covered 4549 of 4800, not 4578: the two are pooled
// apart.) Their errors' correlation is the rows' own.
// Each sigma is at least what the ends' places and the exponent grid leave
// that the median's spread does not show. Rows whose ends share a phase in
// their cells share its error: where the left ends sweep K cells over the
// rows, each phase's error (a periodic function of it, zero on average over
// a cell) is averaged over K periods; what is left, a share |sin(pi K)| /
// (pi K) of one row's, at most 1 / (pi K), counts (one row's where they
// sweep under a third of a cell). (The floor over sqrt(1 + K) independent
// places made the aspect's interval 2.4 times too wide on twin walls, its
// errors' RMS over sigma 0.42; this one 1.07, and 1.00 on an independent
// generator's 36 pools, with the ends at their cells' middles.) The grid's
// is the same in every row: counted whole. The profiler averages over a
// footprint where most rows placed at their walls hold a mixed point at an
// end (PooledShape::footprint); where in the spot's reach such an end lies
// is then not known, the same in every row: beside the rest, whole
// (Silhouette::aspect_mixed_var). (Without it, a generator's walls whose
// points average over a spot as wide as their spacing pooled 0.495-0.499
// +- 0.001-0.002 for 0.500, 20 pools 1.3 sigmas low on average, and the
// second layer's rows, which share the pool, were covered 53-91 %; with it
// +- 0.004-0.005, and 84-100 %.)
PooledShape LayerGrooves::Pooled() const {
  PooledShape pool;
  std::tie(pool.aspect, pool.aspect_sigma) = MedianAndError(aspects_);
  pool.aspect_rows_sigma = pool.aspect_sigma;
  pool.top_noise = tops_.empty() ? NAN : MedianAndError(tops_).first;
  pool.rows = aspects_.size();
  pool.ends_off = EndsOff();
  pool.estimated = estimated_, pool.walls_unsolved = walls_unsolved_, pool.stadium_by_evidence = stadium_only_;
  if (const std::vector<Placed> placed = OfOneFamily(placed_); !placed.empty()) {
    std::vector<double> exponents;
    double lo = INFINITY, hi = -INFINITY, aspect_var = 0.0, exponent_var = 0.0, spacing = 0.0;
    double aspect_grid = 0.0, exponent_grid = 0.0, aspect_mixed = 0.0, exponent_mixed = 0.0;
    std::size_t mixed = 0;
    for (const Placed& p : placed) {
      mixed += p.end_mixed;
      exponents.push_back(p.exponent);
      lo = std::min(lo, p.left_end_mm), hi = std::max(hi, p.left_end_mm), spacing += p.spacing_mm;
      aspect_var += p.aspect_end_var, exponent_var += p.exponent_end_var;
      aspect_grid += p.aspect_grid_var, exponent_grid += p.exponent_grid_var;
      aspect_mixed += p.aspect_mixed_var, exponent_mixed += p.exponent_mixed_var;
    }
    const auto n = static_cast<double>(placed.size());
    pool.footprint = 2 * mixed > placed.size();
    const double cycles = (hi - lo) / (spacing / n);  // K
    const double shared = std::min(1.0, 1.0 / (std::numbers::pi * cycles));
    const auto floor = [&](double ends, double grid) { return std::sqrt(shared * shared * ends / n + grid / n); };
    // A footprint's bias is in no row's spread: beside it, whole.
    const double aspect_spot = pool.footprint ? std::sqrt(aspect_mixed / n) : 0.0;
    const double exponent_spot = pool.footprint ? std::sqrt(exponent_mixed / n) : 0.0;
    pool.aspect_rows_sigma = std::max(pool.aspect_sigma, floor(aspect_var, aspect_grid));
    pool.aspect_footprint_sigma = aspect_spot;
    pool.aspect_sigma = std::hypot(pool.aspect_rows_sigma, aspect_spot);
    if (placed.size() >= kMinExponents) {
      std::tie(pool.exponent, pool.exponent_sigma) = MedianAndError(exponents);
      pool.exponent_sigma =
          std::hypot(std::max(pool.exponent_sigma, floor(exponent_var, exponent_grid)), exponent_spot);
      pool.correlation = ShapeCorrelation(placed);
      pool.exponent_solved = true;
      if (IsStadium(pool.exponent))
        PoolTamped(placed, {floor(aspect_var, aspect_grid), floor(exponent_var, exponent_grid)},
                   {aspect_spot, exponent_spot}, pool);
    }
    // Not an ellipse: a fit's aspect is an ellipse's on another shape (on
    // the twin's walls of exponent 2.6 whose beads hang 2-4 mm off the one
    // below, the rows showing one wall fitted 0.38-0.41 for 0.50, and their
    // pool, 0.417 +- 0.004, corrected a layer 3 % low with none of its
    // intervals covering), and its top misses the bead's (at exponent 3.5,
    // by 3.3-4.0 tolerances over the pool: the layers refused): the aspect
    // and the tops over the rows placed at their walls.
    if (pool.AspectAtWalls()) {
      std::vector<double> aspects, tops;
      for (const Placed& p : placed) {
        aspects.push_back(p.aspect);
        if (std::isfinite(p.top)) tops.push_back(p.top);
      }
      pool.top_noise = tops.empty() ? NAN : MedianAndError(tops).first;
      std::tie(pool.aspect, pool.aspect_sigma) = MedianAndError(aspects);
      pool.aspect_rows_sigma = std::max(pool.aspect_sigma, floor(aspect_var, aspect_grid));
      pool.aspect_sigma = std::hypot(pool.aspect_rows_sigma, aspect_spot);
      pool.rows = placed.size();
    }
  }
  // Too few rows placed at their walls, after layers that solved a shape
  // other than the ellipse: that shape's exponent, its rows fitted with it
  // (their aspects its own). (The ellipse assumed, a wall of exponent 1.6
  // whose last layer showed under 10 rows' walls pooled an ellipse's
  // aspect, 0.58 for 0.50, and corrected that layer 13 % high, none of its
  // intervals covering.) The rows' aspects, fitted at that exponent, move
  // with its error: by da/dp times its sigma (AspectByExponent), beside
  // their own spread, the two errors correlated by that share. (Left out, a
  // twin contour's first layer solved 1.9918 +- 0.0034 for an ellipse's 2,
  // the next layer's fits at it pooled 0.4982 +- 0.0005 for 0.5000, and
  // that layer's intervals covered 85 %.)
  if (!pool.exponent_solved)
    if (const auto* carried = Carried()) {
      const PooledShape& c = carried->second;
      pool.exponent = c.exponent, pool.exponent_sigma = c.exponent_sigma, pool.exponent_solved = true;
      pool.half_height_mm = c.half_height_mm, pool.half_height_sigma_mm = c.half_height_sigma_mm;
      pool.width_excess_mm = c.width_excess_mm;
      pool.corner_mm = c.corner_mm, pool.corner_sigma_mm = c.corner_sigma_mm;
      pool.exponent_layer = c.exponent_layer >= 0 ? c.exponent_layer : carried->first;
      // ... and its verdict, where its walls showed that no shape of the
      // model's has its beads' tops and walls: this layer shows too few
      // walls to judge its own, and one material and process lays it. (Not
      // carried, a lens wall seen at points 0.2 mm apart had its third and
      // fourth layers refused by their walls and its sixth, with too few
      // walls, corrected with the third's exponent: 10 % high, half its
      // intervals covering.)
      if (!pool.ends_off && c.ends_off)
        pool.ends_off = true, pool.ends_off_layer = c.ends_off_layer >= 0 ? c.ends_off_layer : carried->first;
      const double induced = AspectByExponent(c.exponent) * c.exponent_sigma;
      pool.aspect_sigma = std::hypot(pool.aspect_sigma, induced);
      pool.correlation = pool.aspect_sigma > 0.0 ? induced / pool.aspect_sigma : 0.0;
      // A tamped bead's shape carried is held at each row's own width
      // (PooledShape::AtWidth), not at the aspect the rows' fits pooled:
      // its tops are judged as it is held. (Judged by the fits' own tops, a
      // generator's tamped wall at 40 mm/s, whose fourth layer's beads
      // showed one wall, had the fits pool an aspect of 1.05 where the
      // layers that solved their own pooled 0.29-0.59, miss by 3.6
      // tolerances, and the layer go uncorrected, its flow 43 % high.)
      if (pool.Tamped()) pool.top_noise = HeldTopNoise(pool);
    }
  return pool;
}

double LayerGrooves::HeldTopNoise(PooledShape pool) const {
  pool.top_noise = NAN;  // (judged here, not by the gate)
  std::vector<double> tops;
  std::optional<HiddenGroove> previous;
  for (const Waiting& w : waiting_) {
    if (tops.size() == kPoolProfiles) break;
    if (!w.points || !w.row.bead.valid()) continue;
    const HiddenGroove g = Estimate(*w.points, *w.under, w.row, previous ? &*previous : nullptr, &pool);
    if (!g.ok) continue;
    previous = g;
    if (const double top = TopOver(g, w.row, w.points->spacing_mm); std::isfinite(top)) tops.push_back(top);
  }
  return tops.empty() ? NAN : MedianAndError(tops).first;
}

// How the waiting rows' fitted aspects move with the exponent they are
// fitted at, da/dp: the median over up to kSlopeRows of them fitted (not
// placed at their walls) at p and p + step. (The step: a tenth, so that the
// aspects' change, some 0.002, stands well over the fits' settling, 1e-3
// mm of b over its 3 mm; a stadium's p is its corner share c, negated:
// a twentieth of c toward the box.)
double LayerGrooves::AspectByExponent(double p) const {
  constexpr std::size_t kSlopeRows = 10;
  const double step = IsStadium(p) ? -0.05 * p : 0.1;
  std::vector<double> slopes;
  for (const Waiting& w : waiting_) {
    if (slopes.size() == kSlopeRows) break;
    if (!w.points || !w.row.bead.valid()) continue;
    const HiddenGroove at = Estimate(*w.points, *w.under, w.row, nullptr, nullptr, p);
    if (!at.ok || at.at_silhouette) continue;
    const HiddenGroove next = Estimate(*w.points, *w.under, w.row, nullptr, nullptr, p + step);
    if (next.ok && !next.at_silhouette) slopes.push_back((next.aspect - at.aspect) / step);
  }
  return slopes.empty() ? 0.0 : MiddleInPlace(slopes);
}

}  // namespace bead::part
