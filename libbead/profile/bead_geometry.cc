#include "libbead/profile/bead_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "libbead/core/median.h"
#include "libbead/profile/bead_heights.h"
#include "libbead/profile/kernel.h"
#include "libbead/profile/vec8.h"

namespace bead {
namespace BEAD_KERNEL {
namespace {

// The bead's feet: from the run [lo, hi] outward while the height stays
// above the noise floor and the points are joined; then one point further
// on each side, the bare surface that brackets the edge; and, where
// `max_rise` is finite, while the height outward does not rise over the one
// before by more than it (over a part's layer below, a gain rising again
// is that layer's wall, not the bead's foot: BeadOptions::max_foot_rise_mm).
// False when a side has no such point (the edge is not seen).
bool ExtendToFeet(const Heights& pts, float floor_mm, float max_gap, float max_rise, std::size_t& lo, std::size_t& hi) {
  const float* h = pts.h;
  const float* s = pts.s;
  const std::size_t n = pts.n;
  auto joined = [&](std::size_t a, std::size_t b) { return s[b] - s[a] <= max_gap; };
  {
    // Eight points at a time, the steps counted from the mask's bits (a
    // foot is a few points: no loop over them).
    using namespace vec;
    const V8 vf = Splat(floor_mm), vg = Splat(max_gap), vr = Splat(max_rise);
    while (lo >= 9) {  // points lo - 8 .. lo - 1, each joined to the next
      const int bits = Bits((Load(h + lo - 8) > vf) & (Load(s + lo - 7) - Load(s + lo - 8) <= vg) &
                            (Load(h + lo - 8) <= Load(h + lo - 7) + vr));
      const int steps = __builtin_clz(~(static_cast<uint32_t>(bits) << 24));  // set bits down from lane 7
      lo -= static_cast<std::size_t>(steps);
      if (steps < 8) break;
    }
    while (hi + 9 < n) {  // points hi + 1 .. hi + 8, each joined to the one before
      const int bits = Bits((Load(h + hi + 1) > vf) & (Load(s + hi + 1) - Load(s + hi) <= vg) &
                            (Load(h + hi + 1) <= Load(h + hi) + vr));
      const int steps = __builtin_ctz(~static_cast<uint32_t>(bits));  // set bits up from lane 0
      hi += static_cast<std::size_t>(steps);
      if (steps < 8) break;
    }
  }
  while (lo > 0 && joined(lo - 1, lo) && h[lo - 1] > floor_mm && h[lo - 1] <= h[lo] + max_rise) --lo;
  while (hi + 1 < n && joined(hi, hi + 1) && h[hi + 1] > floor_mm && h[hi + 1] <= h[hi] + max_rise) ++hi;
  if (lo == 0 || !joined(lo - 1, lo) || hi + 1 >= n || !joined(hi, hi + 1)) return false;
  --lo;
  ++hi;
  return true;
}

// Trapezoids from the bare point to the bare point: area, first moment
// along the line, and the sum of squared spacings (for the uncertainty).
struct Integrals {
  float area = 0, moment = 0, ds2 = 0;
};
Integrals Integrate(const float* h, const float* s, std::size_t lo, std::size_t hi) {
  using namespace vec;
  V8 v_area{}, v_moment{}, v_ds2{};
  auto add_pieces = [&](std::size_t at, M8 lanes) {  // the pieces from points at .. at + 7
    const V8 s0 = Load(s + at), s1 = Load(s + at + 1);
    const V8 ds = Select(lanes, s1 - s0, V8{});
    const V8 piece = (Load(h + at) + Load(h + at + 1)) * ds;  // twice the trapezoid
    v_area += piece;
    v_moment += piece * (s0 + s1);
    v_ds2 += ds * ds;
  };
  std::size_t k = lo;
  for (; k + 8 <= hi; k += 8) add_pieces(k, ~M8{});
  if (k < hi && hi - lo >= 8) {
    add_pieces(hi - 8, LanesFrom(hi - 8, k));
    k = hi;
  }
  Integrals r{0.5f * Sum(v_area), 0.25f * Sum(v_moment), Sum(v_ds2)};
  for (; k < hi; ++k) {
    const float ds = s[k + 1] - s[k];
    const float piece = 0.5f * (h[k] + h[k + 1]) * ds;
    r.area += piece;
    r.moment += piece * 0.5f * (s[k] + s[k + 1]);
    r.ds2 += ds * ds;
  }
  return r;
}

// Robust maximum over the run [first, last]: the largest median of three
// neighbouring heights.
float RobustHeight(const float* h, std::size_t first, std::size_t last) {
  using namespace vec;
  V8 v_height = Splat(-1.0f);
  auto add_heights = [&](std::size_t at, M8 lanes) {  // the medians about points at .. at + 7
    const V8 med = vec::Median3(Load(h + at - 1), Load(h + at), Load(h + at + 1));
    v_height = Max(v_height, Select(lanes, med, Splat(-1.0f)));
  };
  std::size_t k = first;
  for (; k + 8 <= last + 1; k += 8) add_heights(k, ~M8{});
  if (k <= last && last - first >= 8) {
    add_heights(last - 7, LanesFrom(last - 7, k));
    k = last + 1;
  }
  float height = MaxOf(v_height);
  for (; k <= last; ++k) height = std::max(height, Median3(h[k - 1], h[k], h[k + 1]));
  return height;
}

// One edge's piece by the sub-sample model in place of its trapezoids. It
// takes the first three bead samples inside the edge that are not bridged
// spikes (a spike counts as a missing point: it lies on the chord its
// neighbours span), and needs all three.
struct Side {
  EdgePiece piece;
  double trap = 0.0, trap_moment = 0.0, first_s = 0.0;
};
Side EdgeSide(const Heights& pts, const ProfileWorkspace& w, std::size_t lo, std::size_t hi, std::size_t bare, int dir,
              float floor_mm) {  // dir: +1 inward from lo, -1 inward from hi
  const float* h = pts.h;
  const float* s = pts.s;
  auto is_spike = [&](std::size_t k) { return w.n_spikes > 0 && SpikesWithin(w, k, k) > 0; };
  Side out;
  std::size_t at[3];
  std::size_t k = bare;
  for (int found = 0; found < 3;) {
    k = dir > 0 ? k + 1 : k - 1;
    if (k == lo || k == hi) break;  // reached the other bare sample
    if (!is_spike(k)) at[found++] = k;
    if (found == 3) break;
  }
  const std::size_t i1 = (k == lo || k == hi) ? (dir > 0 ? lo + 1 : hi - 1) : at[0];
  for (std::size_t j = std::min(bare, i1); j < std::max(bare, i1); ++j) {
    const double piece = 0.5 * (double(h[j]) + h[j + 1]) * (double(s[j + 1]) - s[j]);
    out.trap += piece;
    out.trap_moment += piece * 0.5 * (double(s[j]) + s[j + 1]);
  }
  const double gap = std::abs(double(s[i1]) - s[bare]);
  out.first_s = s[i1];
  out.piece = {out.trap, 0.5 * gap, 0.25 * gap};
  if (k != lo && k != hi)
    out.piece = EdgeModel(gap, out.trap, h[at[0]], std::abs(double(s[at[1]]) - s[at[0]]), h[at[1]],
                          std::abs(double(s[at[2]]) - s[at[0]]), h[at[2]], floor_mm);
  return out;
}

// The geometry from the bead's bare points lo and hi: its area and
// centre with the edge pieces, width, height, the area's uncertainty and
// the points dropped between them.
void Finish(const PointSet& p, const ReferenceLine& line, const Heights& pts, const ProfileWorkspace& w, std::size_t lo,
            std::size_t hi, const Run& run, float floor_mm, BeadGeometry& g) {
  const float* h = pts.h;
  const float* s = pts.s;
  const Integrals in = Integrate(h, s, lo, hi);
  const Side foot_l = EdgeSide(pts, w, lo, hi, lo, +1, floor_mm), foot_r = EdgeSide(pts, w, lo, hi, hi, -1, floor_mm);
  const double s_left = foot_l.first_s - foot_l.piece.reach, s_right = foot_r.first_s + foot_r.piece.reach;
  const double area_d = double(in.area) - foot_l.trap - foot_r.trap + foot_l.piece.area + foot_r.piece.area;
  const double moment_d = double(in.moment) - foot_l.trap_moment - foot_r.trap_moment +
                          foot_l.piece.area * (foot_l.first_s - foot_l.piece.centroid) +
                          foot_r.piece.area * (foot_r.first_s + foot_r.piece.centroid);
  g.area_mm2 = area_d;
  const double rms = line.residual_rms_mm;
  const double edge_l = double(h[lo + 1]) * (s[lo + 1] - s[lo]), edge_r = double(h[hi - 1]) * (s[hi] - s[hi - 1]);
  const double width = double(s[hi]) - s[lo];
  g.area_sigma_mm2 = std::sqrt((edge_l * edge_l + edge_r * edge_r) / 12.0 + rms * rms * in.ds2 +
                               rms * rms * width * width / std::max(line.points_used, 1));
  g.width_mm = s_right - s_left;
  g.height_mm = RobustHeight(h, run.first, run.last);
  // A point at along-line position s lies at x = s / sqrt(1 + slope^2).
  const double s_centre = area_d > 0.0 ? moment_d / area_d : 0.5 * (s_left + s_right);
  g.center_x_mm = (pts.s_offset_mm + s_centre) * pts.inv_norm;
  g.left_edge_x_mm = (pts.s_offset_mm + s_left) * pts.inv_norm;
  g.right_edge_x_mm = (pts.s_offset_mm + s_right) * pts.inv_norm;
  // Dropped between the bead's bare points: the view's points there that
  // are not among the heights (dropouts), and the spikes bridged.
  auto view_index = [&](std::size_t k) {
    const std::size_t i = SetIndex(p, w, k);
    return w.mapped ? w.map[i] : static_cast<int32_t>(i);
  };
  const int32_t view_lo = view_index(lo), view_hi = view_index(hi);
  g.dropped_points = std::abs(view_hi - view_lo) - 1 - static_cast<int>(hi - lo - 1) +
                     static_cast<int>(SpikesWithin(w, lo + 1, hi - 1));
  g.status = ProfileStatus::kValid;
}

}  // namespace

BeadGeometry MeasureBead(const PointSet& p, const ReferenceLine& line, const ReferenceArea& left,
                         const ReferenceArea& right, const BeadOptions& options, ProfileWorkspace& w) {
  BeadGeometry g;
  g.reference = line;
  w.n_spikes = 0;
  const auto min_points = static_cast<std::size_t>(std::max(options.min_profile_points, 3));
  if (!line.ok) {
    const bool few = BEAD_KERNEL::CountFiniteZ(p, 0, p.n) < min_points;
    g.status = few ? ProfileStatus::kTooFewPoints : ProfileStatus::kNoReference;
    return g;
  }
  // The bead lies between the reference areas (rig.h): its search takes
  // the points from kAreaMargin points inside the left area (rounded out to
  // a group of eight) to kAreaMargin inside the right one, room for feet
  // that dip below the threshold before the surface is bare. A run reaching
  // into an area marks the profile; what lies beyond the areas (the
  // wheel's rim, a clamp) is not looked at.
  const AreaIndices areas{LowerIndex(p, left.x_min_mm, w.area_hints[0]), UpperIndex(p, left.x_max_mm, w.area_hints[1]),
                          LowerIndex(p, right.x_min_mm, w.area_hints[2]),
                          UpperIndex(p, right.x_max_mm, w.area_hints[3])};
  const std::size_t left_end = areas.left_end, right_begin = areas.right_begin;
  const std::size_t begin = left_end > kAreaMargin ? (left_end - kAreaMargin) / 8 * 8 : 0;
  const std::size_t end = std::max(begin, std::min(p.n, right_begin + kAreaMargin));
  Heights pts = ComputeHeights(p, begin, end, line, w);
  // Too few points in all: the areas' and the search's may overlap, so
  // count the whole profile only when their sum falls short.
  if (pts.n + static_cast<std::size_t>(line.points_available) < min_points &&
      BEAD_KERNEL::CountFiniteZ(p, 0, p.n) < min_points) {
    g.status = ProfileStatus::kTooFewPoints;
    return g;
  }
  w.n_spikes = FindSpikes(pts, static_cast<float>(options.spike_mm), w);
  if (w.n_spikes > 0) BridgeSpikes(pts, w.n_spikes, w);
  g.threshold_mm = std::max(options.min_threshold_mm, options.threshold_sigmas * line.residual_rms_mm);

  const auto max_gap = static_cast<float>(options.max_gap_mm);
  const Run run = LargestRun(p, pts, static_cast<float>(g.threshold_mm), max_gap, areas, w);
  const std::size_t count = run.found ? run.last - run.first + 1 - SpikesWithin(w, run.first, run.last) : 0;
  if (count < static_cast<std::size_t>(std::max(options.min_bead_points, 2))) {
    g.status = ProfileStatus::kNoBead;
    return g;
  }
  g.bead_points = static_cast<int>(count);
  if (TouchesArea(p, run.set_first, run.set_last, areas.left_begin, areas.left_end) ||
      TouchesArea(p, run.set_first, run.set_last, areas.right_begin, areas.right_end)) {
    g.status = ProfileStatus::kBeadInReferenceArea;  // before the feet: the search may cut such a run short
    return g;
  }
  // The bead's feet: from the run outward while the height stays above the
  // noise floor; the point beyond is the bare surface that brackets the edge.
  const auto floor_mm =
      static_cast<float>(std::max(options.edge_floor_sigmas * line.residual_rms_mm, options.min_edge_floor_mm));
  std::size_t lo = run.first, hi = run.last;
  if (!ExtendToFeet(pts, floor_mm, max_gap, static_cast<float>(options.max_foot_rise_mm), lo, hi)) {
    g.status = ProfileStatus::kBeadEdgeNotSeen;
    return g;
  }
  Finish(p, line, pts, w, lo, hi, run, floor_mm, g);
  return g;
}

}  // namespace BEAD_KERNEL
}  // namespace bead
