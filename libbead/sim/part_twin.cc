#include "libbead/sim/part_twin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/sim/head_path.h"
#include "libbead/sim/laid_surface.h"

namespace bead::sim {
namespace {

class WallPrinter {
 public:
  explicit WallPrinter(const PartTwinConfig& c) : c_(c), head_(c), rng_(c.seed) {
    std::normal_distribution<double> wander(0.0, c.wander_sigma_mm), shift(0.0, c.pass_shift_sigma_mm);
    std::uniform_real_distribution<double> phase(0.0, 1.0);
    for (int n = 0; n < c.layers; ++n) {
      wander_.push_back(wander(rng_));
      shift_.push_back(shift(rng_));
      phase_.push_back(phase(rng_));
    }
  }

  double Shift(int n) const { return shift_[n]; }
  double Phase(int n) const { return phase_[n]; }

  const HeadPath& head() const { return head_; }

  // The extruder's flow while the nozzle lays layer n at path p, mm^3/s:
  // the area wave at the nominal speed, whatever the head's speed there.
  double FlowAt(int n, double p) const {
    const double two_pi = 2.0 * std::numbers::pi;
    return c_.head_speed_mm_s * (c_.area_mm2 + c_.area_wave_mm2 * std::sin(two_pi * p / c_.wave_period_mm + 0.7 * n));
  }

  // The bead of layer n at path p: its area (the flow over the head's
  // speed: more where it slows at a corner) and its centre in the bed frame.
  Layer LayerAt(int n, double p) const {
    const double two_pi = 2.0 * std::numbers::pi;
    Layer l;
    l.area = FlowAt(n, p) / head_.SpeedAt(p);
    l.center = shift_[n] + wander_[n] + c_.wander_wave_mm * std::sin(two_pi * p / c_.wander_wave_period_mm + 1.3 * n);
    return l;
  }

  // The envelopes of layers 0..n at path p (the bed first).
  std::vector<Surface> Stack(int n, double p) const {
    Surface bed;
    bed.x0 = -c_.field_half_mm - 6.0;
    bed.dx = TruthGridMm(c_.point_spacing_mm);
    bed.z.assign(static_cast<std::size_t>(2.0 * (c_.field_half_mm + 6.0) / bed.dx) + 1, 0.0);
    // A pipe's top, its crest at x = 0, z = 0, when the bed is a cylinder.
    const double r = c_.bed_radius_mm;
    for (std::size_t k = 0; k < bed.z.size() && r > 0; ++k) {
      const double x = bed.x0 + static_cast<double>(k) * bed.dx;
      bed.z[k] = std::sqrt(std::max(r * r - x * x, 0.0)) - r;
    }
    std::vector<Surface> stack{bed};
    const double a = HalfWidth(p), b = c_.aspect * a;
    for (int k = 0; k <= n; ++k) stack.push_back(Lay(stack.back(), LayerAt(k, p), a, b, nullptr, false, c_.exponent));
    return stack;
  }

  double Noise() { return std::normal_distribution<double>(0.0, c_.noise_mm)(rng_); }

  // The bead's half-width at path p: where the head slows, the bead
  // spreads, its ellipse growing with the material per length it gets (as
  // the square root: the same shape).
  double HalfWidth(double p) const { return 0.5 * c_.width_mm * std::sqrt(c_.head_speed_mm_s / head_.SpeedAt(p)); }

 private:
  const PartTwinConfig& c_;
  HeadPath head_;
  std::mt19937_64 rng_;
  std::vector<double> wander_, shift_, phase_;
};

PartTruthRow Truth(const WallPrinter& printer, const std::vector<Surface>& stack, int n, double p) {
  const Surface &now = stack.back(), &before = stack[stack.size() - 2];
  PartTruthRow t;
  t.layer = n;
  t.path_mm = p;
  const Layer layer = printer.LayerAt(n, p);
  t.area_mm2 = layer.area;
  t.center_x_mm = layer.center;
  t.offset_below_mm = n > 0 ? layer.center - printer.LayerAt(n - 1, p).center : 0.0;
  t.pass_shift_mm = printer.Shift(n);
  double first = 1e300, last = -1e300;
  for (std::size_t k = 0; k < now.z.size(); ++k) {
    const double gain = now.z[k] - before.z[k];
    t.visible_area_mm2 += gain * now.dx;
    if (gain > 1e-9) first = std::min(first, now.x0 + k * now.dx), last = std::max(last, now.x0 + k * now.dx);
  }
  t.width_mm = last - first;
  t.height_mm = now.At(layer.center) - before.At(layer.center);
  return t;
}

}  // namespace

PartTwin SimulatePartWall(const PartTwinConfig& c) {
  if (c.roads > 1) return SimulateRoadLayer(c);
  if (c.alternate && c.shape != PartTwinConfig::Shape::kWall)
    throw Error("part twin: alternate lays a straight wall back and forth, not a contour");
  PartTwin twin;
  WallPrinter printer(c);
  RunArchive& scan = twin.scan;
  scan.part.emplace();
  ProfileBlock& b = scan.profiles;
  SetProfilerPoints(c, b);
  const HeadPath& head = printer.head();
  const double length = head.length_mm(), pass_s = head.pass_s(), layer_s = pass_s + c.return_s;
  twin.path_length_mm = length;
  const double pitch = c.area_mm2 / c.width_mm;
  // Layer n laid from the far end back (alternate, odd n): the place p
  // lies length - p along its pass (a straight wall: the head's speed the
  // same either way).
  const auto backward = [&](int n) { return c.alternate && n % 2 == 1; };
  const auto along = [&](int n, double p) { return backward(n) ? length - p : p; };
  for (int n = 0; n < c.layers; ++n) {
    const double frame_z = n * pitch + c.standoff_mm;
    std::vector<double> places;
    for (double p = printer.Phase(n) * c.profile_spacing_mm; p <= length; p += c.profile_spacing_mm)
      places.push_back(p);
    if (backward(n)) std::reverse(places.begin(), places.end());
    for (double p : places) {
      const std::vector<Surface> stack = printer.Stack(n, p);
      b.t_s.push_back(n * layer_s + head.TimeAt(along(n, p) + c.trail_mm));
      b.encoder.push_back(0);
      const double frame_x = c.frame_x_wave_mm * std::sin(2.0 * std::numbers::pi * p / 23.0);
      const double right_end = printer.LayerAt(n, p).center + printer.HalfWidth(p);
      for (std::size_t j = 0; j < b.points; ++j) {
        const double x = b.x_mm[j] + frame_x + printer.Shift(n);
        const double z = stack.back().At(x) - frame_z + printer.Noise();
        const bool shadowed = x > right_end && x < right_end + c.shadow_mm;
        b.z_mm.push_back(shadowed ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(z));
      }
      scan.part->layer.push_back(n);
      scan.part->path_mm.push_back(p);
      scan.part->frame_z_mm.push_back(frame_z);
      scan.part->frame_x_mm.push_back(frame_x);
      twin.truth.push_back(Truth(printer, stack, n, p));
    }
  }
  AcquisitionLog log;
  for (double t = 0.0; t < c.layers * layer_s; t += 1.0 / c.log_rate_hz) {
    const int n = static_cast<int>(t / layer_s);
    const double into = t - n * layer_s;
    const bool printing = into < pass_s;
    // Printing: `ahead` along the pass; then the travel from where it
    // ended (the profiler past the path's end) to where the next begins.
    const double ahead = head.PathAt(into), sign = backward(n) ? -1.0 : 1.0;
    const double from = backward(n) ? -c.trail_mm : length + c.trail_mm, to = backward(n + 1) ? length : 0.0;
    const double path = printing ? along(n, ahead) : from + (to - from) * (into - pass_s) / c.return_s;
    const bool extruding = printing && ahead <= length;
    log.t_s.push_back(t);
    log.layer.push_back(n);
    log.path_mm.push_back(path);
    log.head_speed_mm_s.push_back(printing ? sign * head.SpeedAt(ahead) : (to - from) / c.return_s);
    const double q = extruding ? printer.FlowAt(n, path) : 0.0;
    log.screw_rpm.push_back(60.0 * q / c.displacement_mm3_per_rev);
  }
  scan.log = std::move(log);
  scan.attributes["rig"] = c.shape == PartTwinConfig::Shape::kContour ? "twin part: a contour with rounded corners"
                                                                      : "twin part: straight wall";
  twin.rig = PartTwinRig(c, "twin-part");
  if (c.bed_radius_mm > 0) twin.rig.part->shape = PartBed::Shape::kCylinder, twin.rig.part->radius_mm = c.bed_radius_mm;
  return twin;
}

void SetProfilerPoints(const PartTwinConfig& c, ProfileBlock& b) {
  b.points = static_cast<std::size_t>(std::lround(2.0 * c.field_half_mm / c.point_spacing_mm)) + 1;
  for (std::size_t j = 0; j < b.points; ++j)
    b.x_mm.push_back(static_cast<float>(-c.field_half_mm + static_cast<double>(j) * c.point_spacing_mm));
}

double ReferenceWidthMm(const PartTwinConfig& c) { return std::min(5.0, 0.25 * c.field_half_mm); }

Rig PartTwinRig(const PartTwinConfig& c, const std::string& name) {
  Rig rig;
  rig.name = name;
  rig.has_wheel = false;
  rig.part = PartBed{};
  const double w = ReferenceWidthMm(c);
  rig.reference_left = {-c.field_half_mm, -c.field_half_mm + w};
  rig.reference_right = {c.field_half_mm - w, c.field_half_mm};
  return rig;
}

}  // namespace bead::sim
