// The surface a part's bead was laid on (format 1.1): the scan of the layer
// below at the same place along the toolpath, in the bed frame (x_bed =
// x + frame_x_mm, z_bed = z + frame_z_mm). A layer's profiles are kept as
// they are measured; when the next layer begins they become the surface
// below (each a row on its points' grid: RowOf) and the layer before is
// let go, its rows and buffers refilled by the layers that follow: memory
// bounded by a layer or two, not by the part.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libbead/core/profile_view.h"
#include "libbead/part/part_kernel.h"

namespace bead::part {

// A surface on a uniform x grid (bed frame): z_k at x0 + k dx, NaN where
// unknown. `variance`: each value's noise variance over one measured
// point's (1 at a measured point, (1 - t)^2 + t^2 a fraction t of the way
// between two); empty: 0 (a fitted line). `at_points`: the grid's values
// are the measured points themselves (a sensor's uniform points): between
// two the variance is (1 - t)^2 v_k + t^2 v_k+1, not linear.
struct SurfaceRow {
  double x0_mm = 0.0, dx_mm = 0.0;
  std::vector<float> z_mm, variance;
  bool at_points = false;
  struct Sample {
    double z, variance, slope;
  };
  static double NaN() { return std::numeric_limits<double>::quiet_NaN(); }
  // Linear between grid values, with dz/dx between the two around x; z and
  // slope NaN outside the grid or next to a NaN.
  Sample SampleAt(double x_mm) const { return SampleAtIndex((x_mm - x0_mm) / dx_mm, 1.0 / dx_mm); }
  // The same at a fractional index u = (x - x0) / dx, given 1 / dx (a
  // caller sampling many places takes the inverse once: no division).
  Sample SampleAtIndex(double u, double per_mm) const {
    std::size_t k = 0;
    double t = 0.0;
    if (!LocateIndex(u, k, t)) return {NaN(), 0.0, NaN()};
    const double rise = static_cast<double>(z_mm[k + 1]) - z_mm[k];
    double v = 0.0;
    if (variance.size() == z_mm.size())
      v = at_points ? (1 - t) * (1 - t) * variance[k] + t * t * variance[k + 1]
                    : variance[k] + t * (variance[k + 1] - variance[k]);
    return {z_mm[k] + t * rise, v, rise * per_mm};
  }
  // SampleAt's z alone (and at a fractional index).
  double At(double x_mm) const { return AtIndex((x_mm - x0_mm) / dx_mm); }
  double AtIndex(double u) const {
    std::size_t k = 0;
    double t = 0.0;
    if (!LocateIndex(u, k, t)) return NaN();
    return z_mm[k] + t * (static_cast<double>(z_mm[k + 1]) - z_mm[k]);
  }
  // Where x falls: a fraction t of the way from value k to value k + 1;
  // false outside the grid.
  bool Locate(double x_mm, std::size_t& k, double& t) const { return LocateIndex((x_mm - x0_mm) / dx_mm, k, t); }
  bool LocateIndex(double u, std::size_t& k, double& t) const {
    if (!(u >= 0.0) || !(u <= static_cast<double>(z_mm.size()) - 1.0) || z_mm.size() < 2) return false;
    k = std::min(static_cast<std::size_t>(u), z_mm.size() - 2);
    t = u - static_cast<double>(k);
    return true;
  }
  double first_mm() const { return x0_mm; }
  double last_mm() const { return x0_mm + dx_mm * static_cast<double>(z_mm.size() - 1); }
};

// The surface under one profile: one row (the bed), or the two profiles of
// the layer below around it along the path, the second weighed w: where
// both are known (1 - w) a + w b, its variance (1 - w)^2 va + w^2 vb;
// where only one is, that one stands for both. The rows are shared, not
// copied: a grid costs nothing to make or keep.
class SurfaceGrid {
 public:
  using Sample = SurfaceRow::Sample;
  SurfaceGrid() = default;
  explicit SurfaceGrid(SurfaceRow row) : a_(std::make_shared<const SurfaceRow>(std::move(row))) {}
  SurfaceGrid(std::shared_ptr<const SurfaceRow> a, std::shared_ptr<const SurfaceRow> b, double w)
      : a_(std::move(a)), b_(std::move(b)), w_(w) {}

  Sample SampleAt(double x_mm) const {
    if (!a_) return {SurfaceRow::NaN(), 0.0, SurfaceRow::NaN()};
    return b_ ? Blend(a_->SampleAt(x_mm), b_->SampleAt(x_mm), w_) : a_->SampleAt(x_mm);
  }
  // SampleAt's z alone (NaN where unknown), and its variance alone.
  double At(double x_mm) const {
    if (!a_) return SurfaceRow::NaN();
    return b_ ? Blend({a_->At(x_mm), 0.0, 0.0}, {b_->At(x_mm), 0.0, 0.0}, w_).z : a_->At(x_mm);
  }
  double VarianceAt(double x_mm) const { return SampleAt(x_mm).variance; }
  // The rule two rows are blended by (the part kernel's Blend is its
  // vector form): both known, (1 - w) a + w b, the variance (1 - w)^2 va +
  // w^2 vb; one known, that one.
  static Sample Blend(const Sample& a, const Sample& b, double w) {
    if (std::isnan(b.z)) return a;
    if (std::isnan(a.z)) return b;
    return {(1 - w) * a.z + w * b.z, (1 - w) * (1 - w) * a.variance + w * w * b.variance,
            (1 - w) * a.slope + w * b.slope};
  }
  // The surface moved by `shift`, sampled at many places (the rows' 1 / dx
  // taken once), and the same rows as the part kernel reads them.
  class Shifted {
   public:
    Shifted(const SurfaceGrid& grid, double shift) : shift_(shift), w_(grid.w_) {
      for (int r = 0; r < 2; ++r) row_[r] = grid.row(r), per_mm_[r] = row_[r] ? 1.0 / row_[r]->dx_mm : 0.0;
    }
    Sample At(double x) const {
      if (!row_[0]) return {SurfaceRow::NaN(), 0.0, SurfaceRow::NaN()};
      const Sample a = row_[0]->SampleAtIndex(Index(0, x), per_mm_[0]);
      return row_[1] ? Blend(a, row_[1]->SampleAtIndex(Index(1, x), per_mm_[1]), w_) : a;
    }
    RowsAt Rows() const {
      RowsAt r;
      r.count = row_[1] ? 2 : row_[0] ? 1 : 0;
      for (int i = 0; i < r.count; ++i)
        r.z[i] = row_[i]->z_mm.data(), r.size[i] = row_[i]->z_mm.size(), r.x0[i] = row_[i]->x0_mm,
        r.per_mm[i] = per_mm_[i];
      r.shift = shift_, r.w = w_;
      return r;
    }

   private:
    double Index(int r, double x) const { return (x - shift_ - row_[r]->x0_mm) * per_mm_[r]; }
    const SurfaceRow* row_[2] = {};
    double per_mm_[2] = {};
    double shift_, w_;
  };
  // The one row this surface is (nullptr where it blends two).
  const SurfaceRow* single_row() const { return b_ ? nullptr : a_.get(); }
  // Its rows (the second nullptr where there is one) and the second's weight.
  const SurfaceRow* row(int r) const { return r == 0 ? a_.get() : b_.get(); }
  double weight() const { return w_; }
  // Where some row is known.
  double first_mm() const { return b_ ? std::min(a_->first_mm(), b_->first_mm()) : a_->first_mm(); }
  double last_mm() const { return b_ ? std::max(a_->last_mm(), b_->last_mm()) : a_->last_mm(); }

 private:
  std::shared_ptr<const SurfaceRow> a_, b_;
  double w_ = 0.0;
};

// The points of a grid from x0 to x1 at dx; 0 when it would hold more than
// kMaxGridPoints (a profile whose x spans metres at micrometre spacing is
// no bead's: refused, not allocated).
inline constexpr std::size_t kMaxGridPoints = std::size_t{1} << 22;
inline std::size_t GridPoints(double x0, double x1, double dx) {
  const double n = (x1 - x0) / dx + 2.0;
  return n > 0 && n < static_cast<double>(kMaxGridPoints) ? static_cast<std::size_t>(n) : 0;
}

// One profile of a layer as the next layer's surface: its valid points in
// the bed frame, increasing in x, and its bead's centre (NaN: not found).
struct StoredProfile {
  double path_mm = 0.0;
  double center_x_mm = std::numeric_limits<double>::quiet_NaN();
  double spacing_mm = 0.05;  // the points' median spacing (part/added_bead.h PointSpacingMm)
  // Its bead's area seen over its own surface below (NaN: not found).
  double area_mm2 = std::numeric_limits<double>::quiet_NaN();
  std::vector<float> x_mm, z_mm;
};

// How the layer below changes between its two profiles around a place
// along the path (the surface there is their blend, SurfaceGrid): the
// second's weight w, the difference of their beads' areas (second less
// first; NaN where either bead is unknown, 0 where one profile stands for
// both), and whether the pair lies where the layer steps (SurfaceBelow:
// Steps).
struct BelowChange {
  double w = 0.0, change_mm2 = 0.0;
  bool step = false;
  // The layer's areas' second difference about the pair (A_j+1 - A_j -
  // A_i + A_i-1, halved: the mean of the two at i and j; 0 where the layer
  // has no profile beyond either end).
  double bend_mm2 = 0.0;
  // The variance the blend leaves where the layer curves along the path
  // (no step): a straight blend of a quadratic misses it by w (1 - w) / 2
  // times its second difference over the pair. (Profiles 3-4 mm apart
  // along the twin's contour, whose beads follow a wave of 40 mm and bulge
  // at its corners: the blend was off by up to 0.5 mm^2 at sigmas of
  // 0.03-0.1, some layers' intervals covering 55-65 %.)
  double BendVariance() const {
    const double miss = 0.5 * w * (1.0 - w) * bend_mm2;
    return step || !std::isfinite(miss) ? 0.0 : miss * miss;
  }
  // The variance the blend leaves in an area measured on it where the
  // layer steps: the change between the two profiles happens somewhere
  // between them, not spread over them as the blend spreads it. Where it
  // lies before the place (chance w) the surface is the second's, after it
  // (1 - w) the first's; the blend is off by (1 - w) D or w D: w (1 - w) D^2.
  double Variance() const { return step && std::isfinite(change_mm2) ? w * (1.0 - w) * change_mm2 * change_mm2 : 0.0; }
};

struct SurfaceBelowOptions {
  // The layer below is not known between two of its profiles farther
  // apart than this, nor beyond its ends by more (a stretch not scanned,
  // or profiles too far apart for their blend to stand for what lies
  // between them), mm along the path.
  double max_path_gap_mm = 5.0;
  // A gap between a stored profile's valid points longer than this is
  // not bridged (the surface there is unknown), mm.
  double max_x_gap_mm = 1.0;
};

// Of a layer's profiles (increasing path_of(rows[k]), at least one), the
// two around `path` and the second's weight, as the layer below is blended
// between them; false, with `why`, where they lie more than max_gap apart
// (or, beyond the layer's ends, the nearest lies farther): `layer` names
// the layer below in the message.
template <class Rows, class PathOf>
bool PathNeighbours(const Rows& rows, PathOf path_of, double path, double max_gap, int64_t layer, std::size_t& i,
                    std::size_t& j, double& w, std::string* why) {
  const auto it =
      std::lower_bound(rows.begin(), rows.end(), path, [&](const auto& r, double v) { return path_of(r) < v; });
  j = static_cast<std::size_t>(it - rows.begin());
  if (j == rows.size()) j = rows.size() - 1;
  i = j > 0 && path_of(rows[j]) > path ? j - 1 : j;
  // Between two profiles: their distance apart (the blend spans it all,
  // wherever the place lies in it); beyond the layer's ends: the nearest's.
  // (The farther neighbour's distance refused a layer scanned every 6 mm
  // where its places fell 0.5 mm before the layer below's, and measured
  // the next, whose fell 1.8 mm after them.)
  const double a = path_of(rows[i]), b = path_of(rows[j]);
  const double gap = i == j ? std::abs(path - a) : b - a;
  if (gap > max_gap) {
    if (why)
      *why = "layer " + std::to_string(layer) + "'s profiles around path " + std::to_string(path) +
             " mm lie more than " + std::to_string(max_gap) + " mm apart";
    return false;
  }
  w = b > a ? std::clamp((path - a) / (b - a), 0.0, 1.0) : 0.0;
  return true;
}

class SurfaceBelow {
 public:
  explicit SurfaceBelow(SurfaceBelowOptions options = {}) : options_(options) {}

  // The layer of the profiles that follow. Layer n + 1 after layer n makes
  // layer n the surface below; a layer skipped leaves none.
  void BeginLayer(int64_t layer);
  int64_t layer() const { return layer_; }
  // Adds a measured profile of the current layer (for the next one).
  void Keep(StoredProfile profile) { current_.push_back(std::move(profile)); }
  // A buffer a profile of the layer before held (empty where none is
  // left), for the next profile's points: a layer's profiles and rows
  // reuse the memory of the ones they replace, not the heap's.
  std::vector<float> Spare();

  // The layer below at `path_mm`, interpolated between its two nearest
  // profiles, with its variance; nullopt, with `why`, where the layer
  // below is unknown.
  std::optional<SurfaceGrid> At(double path_mm, std::string* why) const;
  // The bead centre of the layer below at `path_mm` (its own frame).
  double CenterAt(double path_mm) const;
  // How the layer below changes between its two profiles around `path_mm`
  // (a zero change where it is unknown there).
  BelowChange ChangeAt(double path_mm) const;

 private:
  // The two stored profiles around `path_mm` and the weight of the second.
  bool Neighbours(double path_mm, std::size_t& i, std::size_t& j, double& w, std::string* why) const;

  // Whether each profile and the next lie where the layer steps (ChangeAt).
  void Steps();
  // A profile of the layer below, on its grid.
  struct Below {
    double path_mm = 0.0, center_x_mm = 0.0, area_mm2 = 0.0;
    bool step = false;  // it and the next
    std::shared_ptr<SurfaceRow> row;
  };
  SurfaceBelowOptions options_;
  int64_t layer_ = -1;
  bool below_known_ = false;
  std::vector<Below> below_;
  std::vector<StoredProfile> current_;
  std::vector<std::vector<float>> spare_;        // buffers of the layer before's profiles
  mutable std::shared_ptr<SurfaceRow> blended_;  // At's last blend (one caller at a time)
};

// A profile's valid points moved into the bed frame (x + frame_x, z +
// frame_z), increasing in x (a sensor's usually are: sorted only where they
// are not), at `path` along the toolpath, with their spacing; in buffers
// the layer before held (SurfaceBelow::Spare).
StoredProfile InBedFrame(const ProfileView& v, double path, double frame_x, double frame_z, SurfaceBelow& below);

// The values z at increasing points x placed on the grid x[0] + k dx of n
// values, NaN where no point lies (out, resized to n): false where a point
// lies off the grid by more than a hundredth of dx, on the grid point of
// the one before, or beyond the grid's end. A sensor's points with none
// missing are checked in one pass without branches and copied.
bool PlaceOnGrid(std::span<const float> x, std::span<const float> z, double dx, std::size_t n, std::vector<float>& out);

// A stored profile as a surface row: its own points where they lie on a
// uniform grid (a sensor's usually do: nothing is interpolated), each
// missing point bridged linearly where the gap is no longer than max_gap;
// otherwise the points resampled on a grid of an eighth of their spacing
// (an interpolation of that grid is then that of the points).
SurfaceRow RowOf(const StoredProfile& p, double max_gap_mm);
// The same into `row`, its buffers reused.
void RowOf(const StoredProfile& p, double max_gap_mm, SurfaceRow& row);

}  // namespace bead::part
