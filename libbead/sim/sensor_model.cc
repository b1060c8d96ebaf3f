#include "libbead/sim/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bead::sim {
namespace {

using Vec = Eigen::Vector2d;

double Cross(const Vec& a, const Vec& b) { return a.x() * b.y() - a.y() * b.x(); }

// Pose as maps between frames (wheel: s, h; sensor: x, z).
struct Frames {
  double c, sn, xo, zo;
  explicit Frames(const SensorPose& p)
      : c(std::cos(p.roll_rad)), sn(std::sin(p.roll_rad)), xo(p.x_offset_mm), zo(p.z_offset_mm) {}
  Vec SensorFromWheel(const Vec& w) const { return {c * w.x() - sn * w.y() + xo, sn * w.x() + c * w.y() + zo}; }
  Vec WheelFromSensor(const Vec& q) const {
    const double x = q.x() - xo, z = q.y() - zo;
    return {c * x + sn * z, -sn * x + c * z};
  }
  Vec WheelDirection(const Vec& d) const { return {c * d.x() + sn * d.y(), -sn * d.x() + c * d.y()}; }
};

// Parameter t >= 0 where the ray o + t d meets segment [p, q], or +inf.
double HitSegment(const Vec& o, const Vec& d, const Vec& p, const Vec& q) {
  const Vec e = q - p;
  const double den = Cross(d, e);
  if (den == 0.0) return std::numeric_limits<double>::infinity();
  const Vec w = p - o;
  const double t = Cross(w, e) / den;
  const double u = Cross(w, d) / den;
  if (t < 0.0 || u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  return t;
}

struct Box {
  double s_min, s_max, h_max;
};

Box Bounds(const Outline& o) {
  Box b{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 0.0};
  for (const Vec& p : o) {
    b.s_min = std::min(b.s_min, p.x());
    b.s_max = std::max(b.s_max, p.x());
    b.h_max = std::max(b.h_max, p.y());
  }
  return b;
}

// First hit of a ray (wheel frame, d.y < 0) with the outline, else the
// surface h = 0. Returns the parameter t and the index of the edge hit (-1: surface).
std::pair<double, int> FirstHit(const Outline& o, const Box& box, const Vec& origin, const Vec& d) {
  const double t_ground = -origin.y() / d.y();
  double best = t_ground;
  int edge = -1;
  if (o.size() >= 2) {
    // Where the ray crosses h = h_max and h = 0: outside the box's s range, it misses.
    const double t_top = (box.h_max - origin.y()) / d.y();
    const double s_a = origin.x() + std::max(t_top, 0.0) * d.x(), s_b = origin.x() + t_ground * d.x();
    if (std::max(s_a, s_b) >= box.s_min && std::min(s_a, s_b) <= box.s_max) {
      for (std::size_t i = 0; i + 1 < o.size(); ++i) {
        const double t = HitSegment(origin, d, o[i], o[i + 1]);
        if (t < best) {
          best = t;
          edge = static_cast<int>(i);
        }
      }
    }
  }
  return {best, edge};
}

// Parameter where the ray meets the infinite line through p, q.
double HitLine(const Vec& o, const Vec& d, const Vec& p, const Vec& q) { return Cross(p - o, q - p) / Cross(d, q - p); }

}  // namespace

void RenderProfile(const Outline& outline, const SensorPose& pose, std::span<const float> x_grid,
                   std::span<float> z_out) {
  const Frames f(pose);
  const Box box = Bounds(outline);
  const Vec d = f.WheelDirection({0.0, -1.0});
  const double z_top = 1e4;
  for (std::size_t j = 0; j < x_grid.size(); ++j) {
    const Vec origin = f.WheelFromSensor({x_grid[j], z_top});
    const auto [t, edge] = FirstHit(outline, box, origin, d);
    (void)edge;
    z_out[j] = static_cast<float>(z_top - t);
  }
}

void RenderProfileFan(const Outline& outline, const SensorPose& pose, const Fan& fan, std::span<const float> x_target,
                      std::span<float> x_out, std::span<float> z_out) {
  const Frames f(pose);
  const Box box = Bounds(outline);
  const Vec origin = f.WheelFromSensor({fan.x_mm, fan.z_mm});
  for (std::size_t j = 0; j < x_target.size(); ++j) {
    const Vec d = f.WheelDirection(Vec(x_target[j] - fan.x_mm, -fan.z_mm).normalized());
    const auto [t, edge] = FirstHit(outline, box, origin, d);
    (void)edge;
    const Vec hit = f.SensorFromWheel(origin + t * d);
    x_out[j] = static_cast<float>(hit.x());
    z_out[j] = static_cast<float>(hit.y());
  }
}

double VisibleArea(const Outline& outline, const SensorPose& pose, const std::optional<Fan>& fan) {
  if (outline.size() < 2) return 0.0;
  const Frames f(pose);
  const Box box = Bounds(outline);
  // Rays are indexed by a parameter: the angle about the fan origin, or for
  // parallel rays the offset across them. Between the parameters of two
  // consecutive vertices, the first edge hit does not change.
  const Vec origin = fan ? f.WheelFromSensor({fan->x_mm, fan->z_mm}) : Vec(0.0, 0.0);
  const Vec down = f.WheelDirection({0.0, -1.0});
  const Vec across(-down.y(), down.x());
  const double far = 1e4;
  auto param = [&](const Vec& p) {
    if (fan) return std::atan2(p.y() - origin.y(), p.x() - origin.x());
    return across.dot(p);
  };
  auto ray = [&](double a, Vec& o, Vec& d) {
    if (fan) {
      o = origin;
      d = {std::cos(a), std::sin(a)};
    } else {
      d = down;
      o = a * across - far * down;
    }
  };
  std::vector<double> params;
  for (const Vec& p : outline) params.push_back(param(p));
  std::sort(params.begin(), params.end());
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    const double a = params[i], b = params[i + 1];
    if (b - a < 1e-15) continue;
    Vec o, d;
    ray(0.5 * (a + b), o, d);
    const auto [t, edge] = FirstHit(outline, box, o, d);
    if (edge < 0) continue;  // the surface itself: nothing above it
    const Vec& p = outline[static_cast<std::size_t>(edge)];
    const Vec& q = outline[static_cast<std::size_t>(edge) + 1];
    // The slice between the edge's line and the surface, exact for straight edges.
    Vec oa, da, ob, db;
    ray(a, oa, da);
    ray(b, ob, db);
    const Vec ea = oa + HitLine(oa, da, p, q) * da, eb = ob + HitLine(ob, db, p, q) * db;
    const Vec ga = oa + (-oa.y() / da.y()) * da, gb = ob + (-ob.y() / db.y()) * db;
    // Quadrilateral ea, eb, gb, ga (shoelace).
    const Vec poly[4] = {ea, eb, gb, ga};
    double twice = 0.0;
    for (int k = 0; k < 4; ++k) twice += Cross(poly[k], poly[(k + 1) % 4]);
    area += 0.5 * std::abs(twice);
  }
  return area;
}

void AddSensorNoise(std::span<float> z, const SensorNoise& noise, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (float& v : z) {
    double value = v;
    if (noise.z_sigma_mm > 0) value += noise.z_sigma_mm * gauss(rng);
    if (noise.z_quantum_mm > 0) value = noise.z_quantum_mm * std::round(value / noise.z_quantum_mm);
    if (noise.spike_prob > 0 && uni(rng) < noise.spike_prob) {
      const double magnitude = noise.spike_mm * (0.5 + 0.5 * uni(rng));
      value += uni(rng) < 0.5 ? magnitude : -magnitude;
    }
    if (noise.dropout_prob > 0 && uni(rng) < noise.dropout_prob) value = std::numeric_limits<double>::quiet_NaN();
    v = static_cast<float>(value);
  }
}

}  // namespace bead::sim
