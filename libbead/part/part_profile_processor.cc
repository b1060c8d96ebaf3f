#include "libbead/part/part_profile_processor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "libbead/core/median.h"
#include "libbead/part/added_bead.h"
#include "libbead/part/registration.h"
#include "libbead/profile/kernel.h"

namespace bead::part {
namespace {

// Reference areas no point lies in: the bead over the surface below is
// looked for across the whole profile (a part has no bare strip either
// side that every layer keeps; a bead cut by the field's edge has a foot
// not seen and is refused, as on the wheel).
constexpr ReferenceArea kNowhereLeft{-1e30, -1e30}, kNowhereRight{1e30, 1e30};

// The line z = 0 under the heights over the surface below, carrying the
// gains' noise for the threshold and the feet (BeadOptions: so many of
// its residual RMS).
ReferenceLine FlatLine(double noise_mm, int points) {
  ReferenceLine line;
  line.ok = true;
  line.intercept_mm = 0.0, line.slope = 0.0;
  line.residual_rms_mm = noise_mm;
  line.points_used = std::max(points, 1);  // (in the sigma: the line is exact, no fit)
  line.points_available = 0;               // (no reference areas: the heights alone must hold enough)
  return line;
}

}  // namespace

std::size_t PartProfileProcessor::MinPoints() const {
  return static_cast<std::size_t>(std::max(options_.profile.bead.min_profile_points, 3));
}

double PartProfileProcessor::ShiftSigmaLimit(double spacing) const {
  return std::max(options_.max_shift_sigma_mm, spacing);
}

double PartProfileProcessor::Tau(double noise) const {
  const BeadOptions& b = options_.profile.bead;
  return std::max(b.min_threshold_mm, b.threshold_sigmas * noise);
}

void PartProfileProcessor::MoveByFrame(BeadGeometry& g, double frame_x) {
  g.center_x_mm += frame_x, g.left_edge_x_mm += frame_x, g.right_edge_x_mm += frame_x;
}

PartProfileProcessor::PartProfileProcessor(const Rig& rig, const PartProfileOptions& options, std::size_t max_points)
    : rig_(rig),
      options_(options),
      bed_line_(rig.reference_left, rig.reference_right, options.profile, max_points),
      workspace_(max_points),
      kernel_(&ActiveKernel()),
      below_(options.below),
      rows_(options.below),
      part_kernel_(&ActivePartKernel()) {
  below_z_.reserve(max_points), heights_.reserve(max_points);
}

bool PartProfileProcessor::OnTheGrid(std::span<const float> x, double& x0, double& dx) {
  // A sensor's x is the same profile after profile: the last one checked
  // is compared (memcmp, far cheaper than the check), not checked again.
  if (x.size() == grid_x_.size() && !x.empty() && std::memcmp(x.data(), grid_x_.data(), x.size_bytes()) == 0) {
    x0 = grid_x0_, dx = grid_dx_;
    return true;
  }
  if (!UniformGrid(x, x0, dx)) return false;
  grid_x_.assign(x.begin(), x.end()), grid_x0_ = x0, grid_dx_ = dx;
  return true;
}

void PartProfileProcessor::ToGeneralStore() {
  lean_ = false;
  if (rows_.layer() < 0) return;
  const auto stored = [&](const SensorRows::Row& row) {
    const float* z = row.z.data();
    StoredProfile p;
    p.path_mm = row.path_mm, p.spacing_mm = rows_.dx();
    for (std::size_t k = 0; k < row.z.size(); ++k) {
      if (!std::isfinite(z[k])) continue;
      p.x_mm.push_back(static_cast<float>(row.x0_mm + static_cast<double>(k) * rows_.dx()));
      p.z_mm.push_back(z[k]);
    }
    return p;
  };
  if (rows_.below_known()) {
    below_.BeginLayer(rows_.layer() - 1);
    for (const SensorRows::Row& row : rows_.below_rows()) below_.Keep(stored(row));
  }
  below_.BeginLayer(rows_.layer());
  for (const SensorRows::Row& row : rows_.current_rows()) below_.Keep(stored(row));
}

void PartProfileProcessor::StartPass(int64_t layer) {
  layer_ = layer;
  pass_shift_ = kNaN, pass_noise_ = kNaN, pass_hidden_ = 0.0, pass_loose_ = 0.0;
  wide_searches_ = kWideSearches;
}

const PartProfileGeometry& PartProfileProcessor::Process(const ProfileView& view, const PartPlace& place) {
  result_ = PartProfileGeometry{};
  result_.place = place;
  if (place.layer != layer_) StartPass(place.layer);
  if (lean_) {
    double x0 = 0.0, dx = 0.0;
    const bool on_grid = OnTheGrid(view.x_mm, x0, dx) && view.x_mm.size() <= kMaxGridPoints &&
                         (rows_.dx() == 0.0 || std::abs(dx - rows_.dx()) <= 1e-6 * dx);
    if (on_grid) {
      OnSensorRows(view, place, x0, dx);
      return result_;
    }
    ToGeneralStore();
  }
  below_.BeginLayer(place.layer);
  bed_ = InBedFrame(view, place.path_mm, place.frame_x_mm, place.frame_z_mm, below_);
  if (place.layer == 0) {
    OnBed(view);
  } else if (const std::optional<SurfaceGrid> below = below_.At(place.path_mm, &result_.no_surface)) {
    OverBelow(*below);
  }
  const BeadGeometry& g = result_.bead;
  const bool valid = g.status == ProfileStatus::kValid && result_.no_surface.empty();
  bed_.center_x_mm = valid ? g.center_x_mm : kNaN;
  bed_.area_mm2 = valid ? g.area_mm2 : kNaN;
  below_.Keep(std::move(bed_));
  return result_;
}

void PartProfileProcessor::OnBed(const ProfileView& view) {
  if (rig_.part && rig_.part->shape == PartBed::Shape::kCylinder) {
    result_.no_surface = "a cylinder bed's arc is fitted by bead measure, not per profile";
    return;
  }
  result_.bead = bed_line_.Process(view);
  if (!result_.bead.reference.ok) result_.no_surface = "the bed's reference areas hold too few points for its line";
  MoveByFrame(result_.bead, result_.place.frame_x_mm);
}

void PartProfileProcessor::OverBelow(const SurfaceGrid& below) {
  if (bed_.x_mm.size() < MinPoints()) {
    result_.bead.status = ProfileStatus::kTooFewPoints;  // (its values NaN, as the wheel's)
    return;
  }
  // One point's noise, from the pass's first profile (its second
  // differences: added_bead.h), the gains' threshold set on it as the
  // offline registration sets it.
  if (!std::isfinite(pass_noise_)) pass_noise_ = ProfileNoiseMm(bed_.z_mm);
  const double noise = pass_noise_;
  const bool on_grid = on_grid_.Make(bed_.x_mm, bed_.z_mm, below);
  // From the pass's last shift found; before one is, from the offline
  // registration's wide search, on the pass's first two profiles (0.09 to
  // 0.18 ms each on the twin's 801 points: not on every profile of a layer
  // whose shift the layer below does not constrain), then from where it
  // last pointed.
  double s = std::isfinite(pass_shift_) ? pass_shift_ : pass_loose_;
  if (!std::isfinite(pass_shift_) && wide_searches_ > 0) {
    --wide_searches_;
    const RegistrationScale scale{Tau(noise), noise, bed_.spacing_mm};
    const Registration r = part::Register(bed_.x_mm, bed_.z_mm, below, scale, AddedBeadOptions{}, nullptr,
                                          on_grid ? &on_grid_ : nullptr, 0.0, true);
    s = pass_loose_ = r.shift;
    pass_hidden_ = r.hidden_sigma;
  }
  result_.shift_constrained = Register(below, noise, s);
  if (result_.shift_constrained) pass_shift_ = s;
  result_.shift_mm = s;
  // A gain is the new point less the surface below (a point or a blend
  // of two: at most one point's variance again).
  MeasureAt(below, s, noise * std::sqrt(2.0));
}

bool PartProfileProcessor::Register(const SurfaceGrid& below, double noise, double& s) {
  const double tau = Tau(noise);
  const RegistrationScale scale{tau, noise, bed_.spacing_mm};
  const PointsOnGrid* grid = on_grid_.Ready() ? &on_grid_ : nullptr;
  const double start = s;
  // No step where the pass's hidden sigma is over the limit (the sensor's
  // rows' path says why, part_profile_rows.cc): the cost's curvature at
  // the pass's shift, for its sigma, alone.
  const double limit = ShiftSigmaLimit(bed_.spacing_mm);
  const bool may_move = PassMayMove(limit);
  double curvature = 0.0;
  for (int step = 0; step < options_.shift_steps; ++step) {
    const PointsOnGrid::Local l = LocalCost(bed_.x_mm, bed_.z_mm, below, s, scale, grid);
    curvature = l.curvature;
    if (!may_move || !(curvature > 0.0)) break;
    // Gauss-Newton (gain d = z - below(x - s), dd/ds = below's slope): no
    // step beyond a point spacing, where the truncation may change.
    const double ds = std::clamp(-l.gradient / curvature, -bed_.spacing_mm, bed_.spacing_mm);
    s += ds;
    ++result_.shift_steps;
    if (std::abs(ds) < options_.shift_tolerance * bed_.spacing_mm) break;
  }
  // The cost is in noise variances: s's variance is 2 / curvature, mm^2;
  // never under a wall's sampling (spacing / sqrt 12) nor the shifts the
  // pass's first search found the layer below could hide in; constrained
  // only where the layer below slopes beside the new bead, as the offline
  // registration settles its own (part/registration.h).
  Registration r;
  r.shift = s;
  r.sigma = curvature > 0.0 ? std::max(std::sqrt(2.0 / curvature), bed_.spacing_mm / std::sqrt(12.0)) : kNaN;
  r.hidden_sigma = pass_hidden_;
  AddedBeadOptions settle;
  settle.max_shift_sigma_mm = limit;
  SettleShift(bed_.x_mm, bed_.z_mm, below, scale, settle, grid, r);
  result_.shift_sigma_mm = r.sigma;
  if (!r.constrained) s = start;
  return r.constrained;
}

void PartProfileProcessor::MeasureAt(const SurfaceGrid& below, double s, double noise) {
  const std::size_t n = bed_.x_mm.size();
  if (on_grid_.Ready()) {
    on_grid_.BelowAt(s, below_z_);
  } else {
    below_z_.resize(n);
    const SurfaceGrid::Shifted at(below, s);
    for (std::size_t i = 0; i < n; ++i) below_z_[i] = static_cast<float>(at.At(bed_.x_mm[i]).z);
  }
  heights_.resize(n);
  // Each gain at least 0, NaN off the surface below: a gain under 0 is the
  // noise or the layer below's wall interpolated across a cell beside the
  // bead (a bare point 7 mm under, whose trapezoid to the first bead point
  // put the bead's edge 6 mm inside it), as bead measure takes max(d, 0).
  for (std::size_t i = 0; i < n; ++i) {
    const float d = bed_.z_mm[i] - below_z_[i];
    heights_[i] = d < 0.0f ? 0.0f : d;
  }
  MeasureHeights(bed_.x_mm, bed_.z_mm, noise);
}

void PartProfileProcessor::MeasureHeights(std::span<const float> x, std::span<const float> z, double noise) {
  const std::size_t n = x.size();
  if (n > workspace_.capacity()) workspace_.Reserve(n);
  const PointSet points{x.data(), heights_.data(), n};
  // No spikes bridged in the gains: a wall of the layer below between two
  // points makes a one-point gain that is the surface, not a reflection
  // (a bead overhanging the layer below's wall by a spacing lost a third of
  // a mm^2 so), as the offline measurement bridges none.
  BeadOptions bead = options_.profile.bead;
  bead.spike_mm = std::numeric_limits<double>::infinity();
  // A foot stops where the gain rises again by more than six point noises
  // (two gains differ by about two: bead measure's rule, part/added_bead.cc
  // kFootRiseNoises), the layer below's wall interpolated across a cell.
  bead.max_foot_rise_mm = 6.0 * noise / std::sqrt(2.0);
  result_.bead =
      kernel_->measure(points, FlatLine(noise, static_cast<int>(n)), kNowhereLeft, kNowhereRight, bead, workspace_);
  if (result_.bead.status == ProfileStatus::kValid) result_.bead.height_mm = GainAtCrest(x, z);
}

double PartProfileProcessor::GainAtCrest(std::span<const float> x, std::span<const float> z) const {
  const auto first =
      static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), result_.bead.left_edge_x_mm) - x.begin());
  const auto last =
      static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), result_.bead.right_edge_x_mm) - x.begin());
  if (last < first + 3) return result_.bead.height_mm;
  const std::size_t crest = part_kernel_->crest(z.data(), first + 1, last - 1);
  return Median3(heights_[crest - 1], heights_[crest], heights_[crest + 1]);
}

}  // namespace bead::part
