// PartProfileProcessor on a sensor's rows (part/sensor_rows.h): the new
// profile's points and the layer below's lie on the same uniform grid, so
// at a shift every point falls the same fraction of the way between two
// values of each row below (part/part_kernel.h GridRows), the gains, the
// registration's sums and the surface below are a pass each, eight points
// a register, and no row is made or blended first. The rules are the
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

// Ones: an at-points row's variance over one measured point's, every value.
const float* Ones(std::size_t n) {
  thread_local std::vector<float> ones;
  if (ones.size() < n + 16) ones.assign(n + 16, 1.0f);
  return ones.data();
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
  const float* ones = Ones(std::max(below.size[0], below.count == 2 ? below.size[1] : 0));
  for (int r = 0; r < below.count; ++r) {
    const double c = (x0_bed - s - below.x0_mm[r]) / dx, whole = std::floor(c);
    const auto k0 = static_cast<std::ptrdiff_t>(whole);
    rows.t[r] = static_cast<float>(c - whole);
    rows.z[r] = below.z[r] + k0;
    rows.v[r] = ones + k0;
    begin = std::max(begin, -k0);
    end = std::min(end, static_cast<std::ptrdiff_t>(below.size[r]) - 1 - k0);
  }
  end = std::max(end, begin);
  return rows;
}

void PartProfileProcessor::GainsOnRows(const SensorRows::Pair& below, const float* z_bed, double x0_bed, double dx,
                                       std::size_t n, double s) {
  std::ptrdiff_t begin = 0, end = 0;
  const GridRows rows = RowsAt(below, x0_bed, dx, n, s, begin, end);
  below_z_.assign(n, static_cast<float>(kNaN));
  part_kernel_->below_at(rows, begin, end, below_z_.data());
  heights_.resize(n);
  // Each gain at least 0, NaN off the surface below (the general path's
  // MeasureAt says why).
  for (std::size_t i = 0; i < n; ++i) {
    const float d = z_bed[i] - below_z_[i];
    heights_[i] = d < 0.0f ? 0.0f : d;
  }
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
  const BeadOptions& b = options_.profile.bead;
  const RegistrationScale scale{std::max(b.min_threshold_mm, b.threshold_sigmas * noise), noise, dx};
  const Registration r = part::Register(x, z, grid, scale, AddedBeadOptions{}, nullptr, nullptr, 0.0, true);
  pass_loose_ = r.shift;
  pass_hidden_ = r.hidden_sigma;
}

void PartProfileProcessor::OverRows(const ProfileView& view, const SensorRows::Pair& below, const float* z_bed,
                                    double x0_bed, double dx) {
  const std::size_t n = view.z_mm.size();
  if (!std::isfinite(pass_noise_)) pass_noise_ = NoiseOfFinite({z_bed, n}, below_z_);
  const double noise = pass_noise_;
  const BeadOptions& b = options_.profile.bead;
  const double tau = std::max(b.min_threshold_mm, b.threshold_sigmas * noise);
  const GridShared shared{static_cast<float>(noise * noise), static_cast<float>(tau * tau / (noise * noise)),
                          static_cast<float>(1.0 / dx)};
  if (!std::isfinite(pass_shift_) && wide_searches_ > 0) {
    --wide_searches_;
    SearchWide(below, z_bed, x0_bed, dx, n, noise);
  }
  const double start = std::isfinite(pass_shift_) ? pass_shift_ : pass_loose_;
  // Gauss-Newton steps on the truncated cost (the general path's Register).
  double s = start, curvature = 0.0;
  for (int step = 0; step < options_.shift_steps; ++step) {
    std::ptrdiff_t begin = 0, end = 0;
    const GridRows rows = RowsAt(below, x0_bed, dx, n, s, begin, end);
    const GridSums sums = part_kernel_->local(z_bed, rows, begin, end, shared);
    curvature = sums.third;
    if (!(curvature > 0.0)) break;
    const double ds = std::clamp(-sums.second / curvature, -dx, dx);
    s += ds;
    ++result_.shift_steps;
    if (std::abs(ds) < options_.shift_tolerance * dx) break;
  }
  GainsOnRows(below, z_bed, x0_bed, dx, n, s);
  // Settled as the general path settles it (part/registration.h):
  // sigma at least a wall's sampling and the pass's hidden sigma, held to
  // max_shift_sigma_mm or a spacing if larger (that floor is spacing /
  // sqrt 12), the layer below sloped beside the new bead in enough points.
  const RegistrationScale scale{tau, noise, dx};
  const AddedBeadOptions settle;
  result_.shift_sigma_mm =
      curvature > 0.0 ? std::max({std::sqrt(2.0 / curvature), dx / std::sqrt(12.0), pass_hidden_}) : kNaN;
  result_.shift_constrained =
      result_.shift_sigma_mm <= std::max(options_.max_shift_sigma_mm, dx) &&
      FlankPoints(view.x_mm, {z_bed, n}, below_z_, scale, settle.min_feature_points) >= settle.min_feature_points;
  if (result_.shift_constrained) {
    pass_shift_ = s;
  } else if (s != start) {
    s = start;
    GainsOnRows(below, z_bed, x0_bed, dx, n, s);
  }
  result_.shift_mm = s;
  // The kernel in the profiler's frame (heights do not depend on it), its
  // places then moved to the bed's.
  MeasureHeights(view.x_mm, {z_bed, n}, noise * std::sqrt(2.0));
  MoveByFrame(result_.bead, result_.place.frame_x_mm);
}

}  // namespace bead::part
