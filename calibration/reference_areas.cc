#include "calibration/reference_areas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "libbead/core/error.h"

namespace bead::calibration {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

std::string Mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

using Points = std::vector<std::pair<float, float>>;  // x, z (then height) of one profile, x increasing

// The line through the bare surface: the consensus of the profile's
// tenths (the line through two tenths' medians that most others lie on:
// a bead, a rim or a clamp is a minority of them), then least squares
// over the points near it, twice. False when there is no flat surface.
struct SurfaceLine {
  double c = 0.0, slope = 0.0, rms = 0.0;
};
bool ConsensusLine(const Points& points, double lo, double hi, double threshold, std::vector<double>& seg_x,
                   std::vector<double>& seg_z, SurfaceLine& line) {
  struct Seg {
    double x, z;
  };
  std::vector<Seg> segs;
  for (int k = 0; k < 10; ++k) {
    const double a = lo + (hi - lo) * k / 10.0, b = lo + (hi - lo) * (k + 1) / 10.0;
    seg_x.clear(), seg_z.clear();
    for (const auto& [x, z] : points)
      if (x >= a && (x < b || k == 9)) seg_x.push_back(x), seg_z.push_back(z);
    if (seg_x.size() >= 3) segs.push_back({Quantile(seg_x, 0.5), Quantile(seg_z, 0.5)});
  }
  if (segs.size() < 3) return false;
  int most = -1;
  double best_spread = 1e300;
  for (std::size_t i = 0; i < segs.size(); ++i)
    for (std::size_t j = i + 1; j < segs.size(); ++j) {
      const double m = (segs[j].z - segs[i].z) / (segs[j].x - segs[i].x), c0 = segs[i].z - m * segs[i].x;
      int in = 0;
      double spread = 0.0;
      for (const Seg& g : segs) {
        const double r = std::abs(g.z - c0 - m * g.x);
        if (r <= threshold) ++in, spread += r;
      }
      if (in > most || (in == most && spread < best_spread))
        most = in, best_spread = spread, line.c = c0, line.slope = m;
    }
  return most >= 3;  // no three tenths on one line: no flat surface to stand on
}

bool RefineLine(const Points& points, double threshold, SurfaceLine& line) {
  double band = threshold;
  for (int iteration = 0; iteration < 2; ++iteration) {
    double sx = 0, sz = 0, sxx = 0, sxz = 0;
    std::size_t n_in = 0;
    for (const auto& [x, z] : points)
      if (std::abs(z - line.c - line.slope * x) <= band)
        ++n_in, sx += x, sz += z, sxx += double(x) * x, sxz += double(x) * z;
    const double det = double(n_in) * sxx - sx * sx;
    if (n_in < 10 || !(det > 0.0)) return false;
    line.slope = (n_in * sxz - sx * sz) / det;
    line.c = (sz - line.slope * sx) / double(n_in);
    double ss = 0.0;
    for (const auto& [x, z] : points) {
      const double r = z - line.c - line.slope * x;
      if (std::abs(r) <= band) ss += r * r;
    }
    line.rms = std::sqrt(ss / double(n_in));
    band = std::max(4.0 * line.rms, 0.25 * threshold);
  }
  return true;
}

// A point stands up when the median of it and its four nearest
// neighbours does: a reflection's spike (one or two points) does not.
void MarkRaised(const Points& points, double threshold, std::vector<uint8_t>& up) {
  const std::size_t m = points.size();
  up.assign(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    float v[5];
    int k = 0;
    const std::size_t from = std::min(i >= 2 ? i - 2 : 0, m - 5);  // five points at the ends too
    for (std::size_t j = from; j < from + 5; ++j) v[k++] = points[j].second;
    std::nth_element(v, v + k / 2, v + k);
    up[i] = v[k / 2] > threshold;
  }
}

// The bead: the connected raised run with the largest integral that does
// not reach the field's end; its edges halfway to the bare points beyond
// (the feet run below the threshold: the margin covers them). NaN when none.
std::pair<double, double> BeadEdges(const Points& points, const std::vector<uint8_t>& up, double max_gap_mm) {
  double best = 0.0, best_lo = kNaN, best_hi = kNaN;
  std::size_t i = 0;
  while (i < points.size()) {
    if (!up[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    double integral = points[i].second;
    while (j + 1 < points.size() && up[j + 1] && points[j + 1].first - points[j].first <= max_gap_mm)
      integral += points[++j].second;
    // A run reaching the field's end is a rim or a clamp, not the bead.
    if (j - i + 1 >= 3 && integral > best && i > 0 && j + 1 < points.size()) {
      best = integral;
      best_lo = 0.5 * (points[i - 1].first + points[i].first);
      best_hi = 0.5 * (points[j].first + points[j + 1].first);
    }
    i = j + 1;
  }
  return {best_lo, best_hi};
}

}  // namespace

std::size_t ReferenceSurveyor::Bin(double x) const {
  const double k = std::floor((x - x0_) / bin_mm_);
  if (!(k >= 0.0) || k >= static_cast<double>(bins_)) return bins_;
  return static_cast<std::size_t>(k);
}

void ReferenceSurveyor::Add(const ProfileView& profile) {
  ++profiles_;
  points_.clear();
  const std::size_t n = std::min(profile.x_mm.size(), profile.z_mm.size());
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = profile.x_mm[i], z = profile.z_mm[i];
    if (!std::isfinite(x) || !std::isfinite(z)) continue;
    points_.emplace_back(x, z);
    lo = std::min(lo, double(x)), hi = std::max(hi, double(x));
  }
  if (points_.size() < 10 || !(hi > lo)) return;
  std::sort(points_.begin(), points_.end());
  field_min_ = std::min(field_min_, lo), field_max_ = std::max(field_max_, hi);
  if (!grid_) {
    // Bins of two median spacings over the first profile's field, 5 mm
    // wider either side for profiles that reach further.
    std::vector<double> gaps;
    for (std::size_t i = 1; i < points_.size(); ++i) gaps.push_back(points_[i].first - points_[i - 1].first);
    const double spacing = Quantile(gaps, 0.5);
    bin_mm_ = std::max(2.0 * spacing, 1e-3);
    x0_ = lo - 5.0;
    bins_ = std::min<std::size_t>(static_cast<std::size_t>((hi - lo + 10.0) / bin_mm_) + 1, 65535);
    data_count_.assign(bins_, 0), raised_count_.assign(bins_, 0), point_count_.assign(bins_, 0);
    grid_ = true;
  }
  {
    std::vector<double>& gaps = spacings_;  // a few per profile for the run's median spacing
    if (gaps.size() < 4096) gaps.push_back((hi - lo) / double(points_.size() - 1));
  }
  SurfaceLine line;
  if (!ConsensusLine(points_, lo, hi, options_.threshold_mm, seg_x_, seg_z_, line) ||
      !RefineLine(points_, options_.threshold_mm, line))
    return;
  const double c = line.c, slope = line.slope, rms = line.rms;
  ++with_line_;
  const double norm = 1.0 / std::sqrt(1.0 + slope * slope);
  const double threshold = std::max(options_.threshold_mm, options_.threshold_sigmas * rms * norm);
  for (auto& p : points_) p.second = static_cast<float>((p.second - (c + slope * p.first)) * norm);

  MarkRaised(points_, threshold, up_);
  const std::size_t m = points_.size();
  // Data and raised points per bin (each bin once a profile).
  Raised raised;
  std::size_t last_data = bins_, last_raised = bins_;
  for (std::size_t i = 0; i < m; ++i) {
    const auto [x, h] = points_[i];
    const std::size_t b = Bin(x);
    if (b == bins_) continue;
    ++point_count_[b];
    if (b != last_data) ++data_count_[b], last_data = b;
    if (up_[i] && b != last_raised) {
      ++raised_count_[b], last_raised = b;
      raised.bins.push_back(static_cast<uint16_t>(b));
    }
  }
  const auto [best_lo, best_hi] = BeadEdges(points_, up_, options_.max_gap_mm);
  if (!std::isfinite(best_lo)) return;
  left_edges_.push_back(best_lo);
  right_edges_.push_back(best_hi);
  raised_.push_back(std::move(raised));
}

double ReferenceSurveyor::ClearFraction(const ReferenceArea& area) const {
  if (raised_.empty()) return kNaN;
  const std::size_t b0 = Bin(area.x_min_mm), b1 = Bin(area.x_max_mm);
  const std::size_t lo = b0 == bins_ ? 0 : b0, hi = b1 == bins_ ? bins_ - 1 : b1;
  std::size_t clear = 0;
  for (const Raised& r : raised_)
    clear += std::none_of(r.bins.begin(), r.bins.end(), [&](uint16_t b) { return b >= lo && b <= hi; });
  return double(clear) / double(raised_.size());
}

ReferenceSurvey ReferenceSurveyor::Propose() const {
  ReferenceSurvey s;
  s.profiles = profiles_, s.with_line = with_line_, s.with_bead = raised_.size();
  if (with_line_ == 0)
    throw Error("no profile of the " + std::to_string(profiles_) +
                " read has a surface to fit a line to (10 valid points or more, a flat part either side)");
  if (raised_.size() < 10)
    throw Error("a bead stands above the surface in only " + std::to_string(raised_.size()) + " of " +
                std::to_string(with_line_) + " profiles of a field x " + Mm(field_min_) + " .. " + Mm(field_max_) +
                " mm: the areas are proposed from a run with the bead in view and bare surface either side of it");
  s.field_min_mm = field_min_, s.field_max_mm = field_max_;
  s.spacing_mm = Quantile(spacings_, 0.5);
  s.bead_left_mm[0] = Quantile(left_edges_, options_.edge_quantile);
  s.bead_left_mm[1] = Quantile(left_edges_, 0.5);
  s.bead_right_mm[0] = Quantile(right_edges_, 1.0 - options_.edge_quantile);
  s.bead_right_mm[1] = Quantile(right_edges_, 0.5);
  auto good = [&](std::size_t b) {
    return data_count_[b] >= options_.min_data_fraction * double(with_line_) &&
           raised_count_[b] <= options_.max_raised_fraction * double(with_line_);
  };
  auto describe = [&](ProposedArea& a, std::size_t first, std::size_t last) {  // bins [first, last]
    a.area = {std::max(field_min_, x0_ + double(first) * bin_mm_),
              std::min(field_max_, x0_ + double(last + 1) * bin_mm_)};
    double points = 0;
    for (std::size_t b = first; b <= last; ++b) points += point_count_[b];
    a.points_per_profile = points / double(with_line_);
    a.clear_fraction = ClearFraction({x0_ + (double(first) + 0.5) * bin_mm_, x0_ + (double(last) + 0.5) * bin_mm_});
  };
  auto too_narrow = [&](const char* side, double from, double to) {
    return Error(std::string("the bare surface ") + side + " of the bead spans " + Mm(std::max(0.0, to - from)) +
                 " mm (x " + Mm(from) + " .. " + Mm(to) + " mm) before the field ends or something stands up, under " +
                 Mm(options_.min_area_mm) + " mm: the bead's edges over the run reach x " + Mm(s.bead_left_mm[0]) +
                 " .. " + Mm(s.bead_right_mm[0]) + " mm of a field " + Mm(field_min_) + " .. " + Mm(field_max_) +
                 " mm; centre the bead in the sensor's field or narrow --margin-mm");
  };
  // Left: from the bin wholly outside the margin, outward while good.
  {
    const double inner = s.bead_left_mm[0] - options_.margin_mm;
    const double k = std::floor((inner - x0_) / bin_mm_) - 1.0;
    std::size_t last = k >= 0.0 ? static_cast<std::size_t>(std::min(k, double(bins_) - 1)) : bins_;
    std::size_t first = last;
    while (first != bins_ && good(first) && first > 0 && good(first - 1)) --first;
    if (last == bins_ || !good(last)) throw too_narrow("left", inner, inner);
    describe(s.left, first, last);
    if (s.left.area.x_max_mm - s.left.area.x_min_mm < options_.min_area_mm)
      throw too_narrow("left", s.left.area.x_min_mm, s.left.area.x_max_mm);
  }
  {
    const double inner = s.bead_right_mm[0] + options_.margin_mm;
    const double k = std::ceil((inner - x0_) / bin_mm_);
    std::size_t first = k >= 0.0 && k < double(bins_) ? static_cast<std::size_t>(k) : bins_;
    if (first == bins_ || !good(first)) throw too_narrow("right", inner, inner);
    std::size_t last = first;
    while (last + 1 < bins_ && good(last + 1)) ++last;
    describe(s.right, first, last);
    if (s.right.area.x_max_mm - s.right.area.x_min_mm < options_.min_area_mm)
      throw too_narrow("right", s.right.area.x_min_mm, s.right.area.x_max_mm);
  }
  return s;
}

std::size_t SurveyStream(ProfileStream& stream, std::size_t max_profiles, ReferenceSurveyor& surveyor) {
  const std::size_t n = stream.size();
  const std::size_t stride = std::max<std::size_t>(1, (n + max_profiles - 1) / std::max<std::size_t>(max_profiles, 1));
  ProfileBlock block;
  const std::size_t window = stream.WindowRows();
  for (std::size_t begin = 0; begin < n; begin += window) {
    const std::size_t count = std::min(window, n - begin);
    stream.Read(begin, count, block);
    for (std::size_t k = (stride - begin % stride) % stride; k < count; k += stride) surveyor.Add(block.view(k));
  }
  return stride;
}

}  // namespace bead::calibration
