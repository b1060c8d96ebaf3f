// The twin's layer of roads: part_twin.h's SimulateRoadLayer.
#include <cmath>
#include <numbers>
#include <random>

#include "libbead/sim/laid_surface.h"
#include "libbead/sim/part_twin.h"

namespace bead::sim {
namespace {

class RoadPrinter {
 public:
  explicit RoadPrinter(const PartTwinConfig& c) : c_(c), rng_(c.seed) {
    std::normal_distribution<double> wander(0.0, c.wander_sigma_mm);
    for (int k = 0; k < c.roads; ++k) wander_.push_back(wander(rng_));
    phase_ = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  }

  double Phase() const { return phase_; }

  // Road k at path p: its area and its centre in the bed frame.
  Layer RoadAt(int k, double p) const {
    const double two_pi = 2.0 * std::numbers::pi;
    Layer l;
    l.area = c_.area_mm2 + c_.area_wave_mm2 * std::sin(two_pi * p / c_.wave_period_mm + 0.7 * k);
    l.center = (k - 0.5 * (c_.roads - 1)) * c_.road_spacing_mm + wander_[k] + 0.1 * std::sin(two_pi * p / 60.0 + k);
    return l;
  }

  double Noise() { return std::normal_distribution<double>(0.0, c_.noise_mm)(rng_); }

 private:
  const PartTwinConfig& c_;
  std::mt19937_64 rng_;
  std::vector<double> wander_;
  double phase_ = 0.0;
};

// The roads at path p laid left to right on the bed, each road's truth
// beside the surface they leave.
Surface LayRoads(const PartTwinConfig& c, const RoadPrinter& printer, double p, std::size_t profile,
                 std::vector<PartRoadTruth>& truth) {
  Surface s;
  s.x0 = -c.field_half_mm - 6.0;
  s.dx = TruthGridMm(c.point_spacing_mm);
  s.z.assign(static_cast<std::size_t>(2.0 * (c.field_half_mm + 6.0) / s.dx) + 1, 0.0);
  const double a = 0.5 * c.width_mm, b = c.aspect * a;
  const std::size_t first = truth.size();
  for (int k = 0; k < c.roads; ++k) {
    const Layer road = printer.RoadAt(k, p);
    double zc = 0.0;
    s = Lay(s, road, a, b, &zc, /*fill_under=*/true);
    PartRoadTruth t;
    t.profile = profile, t.road = k, t.area_mm2 = road.area, t.center_x_mm = road.center;
    // Where its top meets the bed: its ellipse's chord there, or (its
    // centre above the bed) its full width, filled down to the bed.
    t.width_mm = zc < 0.0 ? 2.0 * a * std::sqrt(std::max(0.0, 1.0 - (zc / b) * (zc / b))) : 2.0 * a;
    t.height_mm = zc + b;
    truth.push_back(t);
  }
  // The naive split: a vertical cut at the lowest point between two centres.
  std::vector<double> cuts{s.x0};
  for (int k = 0; k + 1 < c.roads; ++k) {
    double at = truth[first + k].center_x_mm, low = 1e300;
    for (double x = truth[first + k].center_x_mm; x <= truth[first + k + 1].center_x_mm; x += s.dx)
      if (s.At(x) < low) low = s.At(x), at = x;
    cuts.push_back(at);
  }
  cuts.push_back(s.x0 + static_cast<double>(s.z.size() - 1) * s.dx);
  for (int k = 0; k < c.roads; ++k)
    for (double x = cuts[k]; x < cuts[k + 1]; x += s.dx) truth[first + k].naive_area_mm2 += s.At(x) * s.dx;
  return s;
}

AcquisitionLog RoadsLog(const PartTwinConfig& c, const RoadPrinter& printer, double pass_s) {
  AcquisitionLog log;
  const double road_s = pass_s + c.return_s;
  for (double t = 0.0; t < c.roads * road_s; t += 1.0 / c.log_rate_hz) {
    const int k = static_cast<int>(t / road_s);
    const double into = t - k * road_s;
    const bool printing = into < pass_s;
    const double path = printing ? into * c.head_speed_mm_s : c.length_mm * (1.0 - (into - pass_s) / c.return_s);
    log.t_s.push_back(t);
    log.layer.push_back(0);
    log.path_mm.push_back(path);
    log.head_speed_mm_s.push_back(printing ? c.head_speed_mm_s : -c.length_mm / c.return_s);
    const double q = printing ? printer.RoadAt(k, path).area * c.head_speed_mm_s : 0.0;
    log.screw_rpm.push_back(60.0 * q / c.displacement_mm3_per_rev);
  }
  return log;
}

}  // namespace

PartTwin SimulateRoadLayer(const PartTwinConfig& c) {
  PartTwin twin;
  RoadPrinter printer(c);
  twin.path_length_mm = c.length_mm;
  RunArchive& scan = twin.scan;
  scan.part.emplace();
  ProfileBlock& b = scan.profiles;
  SetProfilerPoints(c, b);
  const double pass_s = c.length_mm / c.head_speed_mm_s, scan_from_s = c.roads * (pass_s + c.return_s);
  for (double p = printer.Phase() * c.profile_spacing_mm; p <= c.length_mm; p += c.profile_spacing_mm) {
    const std::size_t profile = b.t_s.size();
    const Surface s = LayRoads(c, printer, p, profile, twin.road_truth);
    b.t_s.push_back(scan_from_s + p / c.head_speed_mm_s);
    b.encoder.push_back(0);
    for (std::size_t j = 0; j < b.points; ++j)
      b.z_mm.push_back(static_cast<float>(s.At(b.x_mm[j]) - c.standoff_mm + printer.Noise()));
    scan.part->layer.push_back(0);
    scan.part->path_mm.push_back(p);
    scan.part->frame_z_mm.push_back(c.standoff_mm);
    scan.part->frame_x_mm.push_back(0.0);
    PartTruthRow t;  // the layer as one: its roads' material
    t.path_mm = p;
    for (auto r = twin.road_truth.end() - c.roads; r != twin.road_truth.end(); ++r) t.area_mm2 += r->area_mm2;
    t.visible_area_mm2 = t.area_mm2;
    twin.truth.push_back(t);
  }
  scan.log = RoadsLog(c, printer, pass_s);
  scan.attributes["rig"] = "twin part: a layer of roads";
  twin.rig = PartTwinRig(c, "twin-roads");
  return twin;
}

}  // namespace bead::sim
