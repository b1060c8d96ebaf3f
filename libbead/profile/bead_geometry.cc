#include "libbead/profile/bead_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "libbead/profile/median.h"

namespace bead {
namespace {

// Height and along-line position of every ordered point, then drops spikes:
// points standing more than spike_mm off the median of themselves and
// their four nearest neighbours. Leaves the kept points in w.x, w.s, w.h, w.order.
void HeightsWithoutSpikes(const ProfileView& view, const ReferenceLine& line, double spike_mm,
                          ProfileWorkspace& w) {
  const double a = line.intercept_mm, b = line.slope;
  const double inv_norm = 1.0 / std::sqrt(1.0 + b * b);
  const std::size_t n = w.n_valid;
  double* xs = w.x.data();
  double* ss = w.s.data();
  double* hs = w.h.data();
  for (std::size_t k = 0; k < n; ++k) {
    const double x = view.x_mm[w.order[k]];
    const double z = view.z_mm[w.order[k]];
    xs[k] = x;
    hs[k] = (z - a - b * x) * inv_norm;
    ss[k] = (x + b * (z - a)) * inv_norm;
  }
  // Median of five, so two adjacent spikes are caught too; three at the ends.
  // Only where a neighbour jumps by more than spike_mm: otherwise three of
  // the five (the point and both neighbours) lie within spike_mm of the
  // point, so their median does too, and the point is kept.
  bool any = false;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (std::abs(hs[k] - hs[k - 1]) <= spike_mm && std::abs(hs[k] - hs[k + 1]) <= spike_mm) continue;
    const double med = (k >= 2 && k + 2 < n) ? Median5(hs[k - 2], hs[k - 1], hs[k + 1], hs[k + 2], hs[k])
                                             : Median3(hs[k - 1], hs[k], hs[k + 1]);
    if (std::abs(hs[k] - med) > spike_mm) {
      if (!any) std::fill(w.keep.begin(), w.keep.begin() + static_cast<long>(n), uint8_t{1});
      w.keep[k] = 0;
      any = true;
    }
  }
  if (!any) return;
  std::size_t m = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!w.keep[k]) continue;
    w.order[m] = w.order[k];
    xs[m] = xs[k];
    ss[m] = ss[k];
    hs[m] = hs[k];
    ++m;
  }
  w.n_valid = m;
}

struct Run {
  std::size_t first = 0, last = 0;  // inclusive, indices into w.s / w.h
  double integral = -1.0;
};

bool InReference(double x, const ReferenceArea& left, const ReferenceArea& right) {
  return left.Contains(x) || right.Contains(x);
}

// The run of consecutive points above `threshold` (gaps up to max_gap) with
// the largest integral, among runs holding a point outside both areas.
Run LargestRun(const ProfileWorkspace& w, double threshold, double max_gap, const ReferenceArea& left,
               const ReferenceArea& right) {
  Run best, current;
  bool open = false, outside = false;
  const std::size_t n = w.n_valid;
  auto close = [&]() {
    if (open && outside && current.integral > best.integral) best = current;
    open = false;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const bool above = w.h[k] > threshold;
    if (open && (!above || w.s[k] - w.s[k - 1] > max_gap)) close();
    if (!above) continue;
    if (!open) {
      open = true;
      outside = false;
      current = Run{k, k, 0.0};
    } else {
      current.integral += 0.5 * (w.h[k] + w.h[k - 1]) * (w.s[k] - w.s[k - 1]);
      current.last = k;
    }
    outside = outside || !InReference(w.x[k], left, right);
  }
  close();
  return best;
}

// Where the segment from (s_out, h_out) to (s_in, h_in) crosses h = 0,
// clamped to the segment.
double EdgeCrossing(double s_out, double h_out, double s_in, double h_in) {
  if (!(h_in > h_out)) return s_out;
  const double t = std::clamp(-h_out / (h_in - h_out), 0.0, 1.0);
  return s_out + t * (s_in - s_out);
}

}  // namespace

const char* StatusName(ProfileStatus status) {
  switch (status) {
    case ProfileStatus::kValid: return "valid";
    case ProfileStatus::kTooFewPoints: return "too_few_points";
    case ProfileStatus::kNoReference: return "no_reference";
    case ProfileStatus::kNoBead: return "no_bead";
    case ProfileStatus::kBeadEdgeNotSeen: return "bead_edge_not_seen";
    case ProfileStatus::kBeadInReferenceArea: return "bead_in_reference_area";
  }
  return "unknown";
}

BeadGeometry MeasureBead(const ProfileView& view, const ReferenceLine& line, const ReferenceArea& left,
                         const ReferenceArea& right, const BeadOptions& options, ProfileWorkspace& w) {
  BeadGeometry g;
  g.reference = line;
  if (w.n_valid < static_cast<std::size_t>(std::max(options.min_profile_points, 3))) {
    g.status = ProfileStatus::kTooFewPoints;
    return g;
  }
  if (!line.ok) {
    g.status = ProfileStatus::kNoReference;
    return g;
  }
  HeightsWithoutSpikes(view, line, options.spike_mm, w);
  g.threshold_mm = std::max(options.min_threshold_mm, options.threshold_sigmas * line.residual_rms_mm);

  const Run run = LargestRun(w, g.threshold_mm, options.max_gap_mm, left, right);
  const std::size_t count = run.integral < 0.0 ? 0 : run.last - run.first + 1;
  if (count < static_cast<std::size_t>(std::max(options.min_bead_points, 2))) {
    g.status = ProfileStatus::kNoBead;
    return g;
  }
  g.bead_points = static_cast<int>(count);
  // The bead's feet: from the run outward while the height stays above the
  // noise floor; the point beyond is the bare surface that brackets the edge.
  const double floor_mm = std::max(options.edge_floor_sigmas * line.residual_rms_mm, options.min_edge_floor_mm);
  const std::size_t n = w.n_valid;
  std::size_t lo = run.first, hi = run.last;
  auto joined = [&](std::size_t a, std::size_t b) { return w.s[b] - w.s[a] <= options.max_gap_mm; };
  while (lo > 0 && joined(lo - 1, lo) && w.h[lo - 1] > floor_mm) --lo;
  while (hi + 1 < n && joined(hi, hi + 1) && w.h[hi + 1] > floor_mm) ++hi;
  if (lo == 0 || !joined(lo - 1, lo) || hi + 1 >= n || !joined(hi, hi + 1)) {
    g.status = ProfileStatus::kBeadEdgeNotSeen;
    return g;
  }
  --lo;
  ++hi;
  for (std::size_t k = run.first; k <= run.last; ++k) {
    if (InReference(w.x[k], left, right)) {
      g.status = ProfileStatus::kBeadInReferenceArea;
      return g;
    }
  }

  double area = 0.0, moment = 0.0, height = -1.0, ds2 = 0.0;
  for (std::size_t k = lo; k < hi; ++k) {
    const double ds = w.s[k + 1] - w.s[k];
    const double piece = 0.5 * (w.h[k] + w.h[k + 1]) * ds;
    area += piece;
    moment += piece * 0.5 * (w.s[k] + w.s[k + 1]);
    ds2 += ds * ds;
  }
  for (std::size_t k = run.first; k <= run.last; ++k)
    height = std::max(height, Median3(w.h[k - 1], w.h[k], w.h[k + 1]));

  const double inv_norm = 1.0 / std::sqrt(1.0 + line.slope * line.slope);
  const double s_left = EdgeCrossing(w.s[lo], w.h[lo], w.s[lo + 1], w.h[lo + 1]);
  const double s_right = EdgeCrossing(w.s[hi], w.h[hi], w.s[hi - 1], w.h[hi - 1]);
  g.area_mm2 = area;
  const double rms = line.residual_rms_mm;
  const double edge_l = w.h[lo + 1] * (w.s[lo + 1] - w.s[lo]), edge_r = w.h[hi - 1] * (w.s[hi] - w.s[hi - 1]);
  const double width = w.s[hi] - w.s[lo];
  g.area_sigma_mm2 = std::sqrt((edge_l * edge_l + edge_r * edge_r) / 12.0 + rms * rms * ds2 +
                               rms * rms * width * width / std::max(line.points_used, 1));
  g.width_mm = s_right - s_left;
  g.height_mm = height;
  // A point at along-line position s lies at x = s / sqrt(1 + slope^2).
  g.center_x_mm = (area > 0.0 ? moment / area : 0.5 * (s_left + s_right)) * inv_norm;
  g.left_edge_x_mm = s_left * inv_norm;
  g.right_edge_x_mm = s_right * inv_norm;
  g.dropped_points = std::abs(w.order[hi] - w.order[lo]) - 1 - static_cast<int>(hi - lo - 1);
  g.status = ProfileStatus::kValid;
  return g;
}

}  // namespace bead
