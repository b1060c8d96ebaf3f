// PartProfileProcessor on a sensor's rows (part/sensor_rows.h): the new
// profile's points and the layer below's lie on the same uniform grid, so
// at a shift every point falls the same fraction of the way between two
// values of each row below (part/part_kernel.h GridRows): the surface
// below, the gains and the registration's sums are one pass, eight points a
// register, and no row is made or blended first. The rules are the
// general path's (part_profile_processor.cc), to a float's rounding.
#include <algorithm>
#include <cmath>
#include <memory>

#include "libbead/part/added_bead.h"
#include "libbead/part/part_profile_processor.h"
#include "libbead/part/registration.h"

namespace bead::part {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One point's noise from the finite values of z (the pass's first profile;
// added_bead.h's second differences), NaN-free as ProfileNoiseMm needs.
double NoiseOfFinite(std::span<const float> z, std::vector<float>& scratch) {
  scratch.clear();
  for (const float v : z)
    if (std::isfinite(v)) scratch.push_back(v);
  return ProfileNoiseMm(scratch);
}

}  // namespace

void PartProfileProcessor::OnSensorRows(const ProfileView& view, const PartPlace& place, double x0, double dx) {
  rows_.BeginLayer(place.layer);
  const double x0_bed = x0 + place.frame_x_mm;
  const float* z_bed = rows_.Keep(place.path_mm, x0_bed, dx, view.z_mm, place.frame_z_mm);
  if (place.layer == 0) {
    OnBed(view);
    return;
  }
  SensorRows::Pair below;
  if (!rows_.At(place.path_mm, below, &result_.no_surface)) return;
  OverRows(view, below, z_bed, x0_bed, dx);
}

GridRows PartProfileProcessor::RowsAt(const SensorRows::Pair& below, double x0_bed, double dx, std::size_t n, double s,
                                      std::ptrdiff_t& begin, std::ptrdiff_t& end) const {
  // PointsOnGrid::Inside's arithmetic (part/grid_costs.cc): index i of the
  // new points reads values i + k0 and i + k0 + 1 of a row, a fraction t
  // of the way; inside every row where both are the row's.
  GridRows rows;
  rows.count = below.count;
  rows.w = static_cast<float>(below.w);
  begin = 0, end = static_cast<std::ptrdiff_t>(n);
  for (int r = 0; r < below.count; ++r) {
    const double c = (x0_bed - s - below.x0_mm[r]) / dx, whole = std::floor(c);
    const auto k0 = static_cast<std::ptrdiff_t>(whole);
    rows.t[r] = static_cast<float>(c - whole);
    rows.z[r] = below.z[r] + k0;
    begin = std::max(begin, -k0);
    end = std::min(end, static_cast<std::ptrdiff_t>(below.size[r]) - 1 - k0);
  }
  // (A row far beside the new points, a frame's jump: none inside.)
  begin = std::min(begin, static_cast<std::ptrdiff_t>(n));
  end = std::max(end, begin);
  return rows;
}

GridSums PartProfileProcessor::GainsOnRows(const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx,
                                           std::size_t n, double s, const GridShared& shared) {
  std::ptrdiff_t begin = 0, end = 0;
  const GridRows rows = RowsAt(below, x0_bed, dx, n, s, begin, end);
  below_z_.resize(n), heights_.resize(n);
  // NaN off the surface below; within it each gain at least 0 (the
  // general path's MeasureAt says why), and the registration's sums.
  const auto nan = static_cast<float>(kNaN);
  std::fill(below_z_.begin(), below_z_.begin() + begin, nan), std::fill(below_z_.begin() + end, below_z_.end(), nan);
  std::fill(heights_.begin(), heights_.begin() + begin, nan), std::fill(heights_.begin() + end, heights_.end(), nan);
  return part_kernel_->gains(z_bed, rows, begin, end, shared, below_z_.data(), heights_.data());
}

void PartProfileProcessor::SearchWide(const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx,
                                      std::size_t n, double noise) {
  // The general store's forms of the two rows and of the new points (the
  // pass's first two profiles only).
  std::vector<float> x, z;
  for (std::size_t k = 0; k < n; ++k)
    if (std::isfinite(z_bed[k]))
      x.push_back(static_cast<float>(x0_bed + static_cast<double>(k) * dx)), z.push_back(z_bed[k]);
  std::shared_ptr<SurfaceRow> row[2];
  for (int r = 0; r < below.count; ++r) {
    row[r] = std::make_shared<SurfaceRow>();
    row[r]->x0_mm = below.x0_mm[r], row[r]->dx_mm = dx, row[r]->at_points = true;
    row[r]->z_mm.assign(below.z[r], below.z[r] + below.size[r]);
    row[r]->variance.assign(below.size[r], 1.0f);
  }
  const SurfaceGrid grid = below.count == 2 ? SurfaceGrid(row[0], row[1], below.w) : SurfaceGrid(row[0], nullptr, 0.0);
  const RegistrationScale scale{Tau(noise), noise, dx};
  const Registration r = part::Register(x, z, grid, scale, AddedBeadOptions{}, nullptr, nullptr, 0.0, true);
  pass_loose_ = r.shift;
  pass_hidden_ = r.hidden_sigma;
}

void PartProfileProcessor::OverRows(const ProfileView& view, const SensorRows::Pair& below, const float* z_bed,
                                    double x0_bed, double dx) {
  const std::size_t n = view.z_mm.size();
  if (!std::isfinite(pass_noise_)) {
    // Not from a profile of too few points (the sensor saw nothing: its
    // noise would be the floor's, for the whole pass).
    const double noise = NoiseOfFinite({z_bed, n}, below_z_);
    if (below_z_.size() < MinPoints()) {
      result_.bead.status = ProfileStatus::kTooFewPoints;
      return;
    }
    pass_noise_ = noise;
  }
  const double noise = pass_noise_;
  const double tau = Tau(noise);
  const GridShared shared{static_cast<float>(noise * noise), static_cast<float>(tau * tau / (noise * noise)),
                          static_cast<float>(1.0 / dx)};
  if (!std::isfinite(pass_shift_) && wide_searches_ > 0) {
    --wide_searches_;
    SearchWide(below, z_bed, x0_bed, dx, n, noise);
  }
  const double start = std::isfinite(pass_shift_) ? pass_shift_ : pass_loose_;
  // Gauss-Newton steps on the truncated cost (the general path's
  // Register), its sums taken in the pass that makes the gains: a step
  // under the tolerance is this profile's estimate, the gains left where
  // they were made (within a quarter spacing of it: a wall of the layer
  // below 1 mm higher on one side moves the area by 0.25 spacing x 1 mm).
  // No step where the pass's hidden sigma, a floor under every sigma in
  // it, is over the limit: no profile of the pass can be constrained, its
  // shift is the pass's (one pass makes the gains there; stepping away and
  // back made a third of the twin wall's profiles on such a layer three).
  const double limit = ShiftSigmaLimit(dx);
  const bool may_move = PassMayMove(limit);
  double s = start, curvature = 0.0, estimate = start;
  for (int step = 0;; ++step) {
    const GridSums sums = GainsOnRows(below, z_bed, x0_bed, dx, n, s, shared);
    curvature = sums.third;
    if (!may_move || step >= options_.shift_steps || !(curvature > 0.0)) break;
    const double ds = std::clamp(-sums.second / curvature, -dx, dx);
    estimate = s + ds;
    ++result_.shift_steps;
    if (std::abs(ds) < options_.shift_tolerance * dx || step + 1 == options_.shift_steps) break;
    s = estimate;
  }
  // Settled as the general path settles it (part/registration.h):
  // sigma at least a wall's sampling and the pass's hidden sigma, held to
  // max_shift_sigma_mm or a spacing if larger (that floor is spacing /
  // sqrt 12), the layer below sloped beside the new bead in enough points.
  const RegistrationScale scale{tau, noise, dx};
  const AddedBeadOptions settle;
  result_.shift_sigma_mm =
      curvature > 0.0 ? std::max({std::sqrt(2.0 / curvature), dx / std::sqrt(12.0), pass_hidden_}) : kNaN;
  result_.shift_constrained =
      result_.shift_sigma_mm <= limit &&
      FlankPoints(view.x_mm, {z_bed, n}, below_z_, scale, settle.min_feature_points) >= settle.min_feature_points;
  // The gains made again only where they lie farther from the shift kept
  // than the tolerance (the steps ran out; or unconstrained, the pass's).
  const double kept = result_.shift_constrained ? estimate : start;
  if (std::abs(kept - s) >= options_.shift_tolerance * dx) GainsOnRows(below, z_bed, x0_bed, dx, n, kept, shared);
  s = kept;
  if (result_.shift_constrained) pass_shift_ = s;
  result_.shift_mm = s;
  // The kernel in the profiler's frame (heights do not depend on it), its
  // places then moved to the bed's.
  MeasureHeights(view.x_mm, {z_bed, n}, noise * std::sqrt(2.0));
  MoveByFrame(result_.bead, result_.place.frame_x_mm);
}

}  // namespace bead::part
