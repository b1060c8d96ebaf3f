#include "libbead/sim/bead_shapes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bead::sim {
namespace {

void Arc(Outline& o, double cx, double cy, double r, double from, double to, int steps) {
  for (int i = 1; i <= steps; ++i) {
    const double a = from + (to - from) * i / steps;
    o.emplace_back(cx + r * std::cos(a), cy + r * std::sin(a));
  }
}

Outline RoundedRectangle(double w, double h, double rb, double rt, int vertices) {
  const int arc = std::max(2, (vertices - 4) / 4);
  const double pi = std::numbers::pi;
  Outline o;
  o.emplace_back(-(w / 2 - rb), 0.0);
  if (rb > 0) Arc(o, -(w / 2 - rb), rb, rb, -pi / 2, -pi, arc);  // bottom left, curling out
  o.emplace_back(-w / 2, h - rt);
  if (rt > 0) Arc(o, -(w / 2 - rt), h - rt, rt, pi, pi / 2, arc);
  o.emplace_back(w / 2 - rt, h);
  if (rt > 0) Arc(o, w / 2 - rt, h - rt, rt, pi / 2, 0.0, arc);
  o.emplace_back(w / 2, rb);
  if (rb > 0) Arc(o, w / 2 - rb, rb, rb, 0.0, -pi / 2, arc);  // bottom right, curling in
  // Drop repeated points (zero radii).
  o.erase(std::unique(o.begin(), o.end(),
                      [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (a - b).norm() < 1e-12; }),
          o.end());
  return o;
}

Outline CutSuperellipse(double a, double b, double c, double n_top, double n_bottom, int vertices) {
  // Parametric: x = a sgn(cos t) |cos t|^(2/n), y = c + b sgn(sin t) |sin t|^(2/n),
  // with n = n_top above the widest point (sin t > 0) and n_bottom below.
  auto pw = [](double v, double n) { return std::copysign(std::pow(std::abs(v), 2.0 / n), v); };
  const double t0 = -std::asin(std::pow(c / b, n_bottom / 2.0));  // where y = 0, on the right
  Outline o;
  for (int i = 0; i < vertices; ++i) {
    const double t = (std::numbers::pi - t0) + (2 * t0 - std::numbers::pi) * i / (vertices - 1);
    const double n = std::sin(t) >= 0 ? n_top : n_bottom;
    o.emplace_back(a * pw(std::cos(t), n), std::max(0.0, c + b * pw(std::sin(t), n)));
  }
  o.front().y() = 0.0;
  o.back().y() = 0.0;
  return o;
}

}  // namespace

Outline UnitBeadOutline(const BeadConfig& c) {
  switch (c.shape) {
    case BeadConfig::Shape::kRoundedRectangle:
      return RoundedRectangle(c.aspect, 1.0, c.bottom_radius_frac, c.top_radius_frac, c.outline_vertices);
    case BeadConfig::Shape::kSuperellipse: {
      const double b = 1.0 / (1.0 + c.center_lift_frac);
      return CutSuperellipse(c.aspect / 2, b, c.center_lift_frac * b, c.exponent,
                             c.bottom_exponent > 0 ? c.bottom_exponent : c.exponent, c.outline_vertices);
    }
    case BeadConfig::Shape::kParabola:
      return ParabolaOutline(c.aspect, 1.0, 0.0, c.outline_vertices);
  }
  return {};
}

Outline ScaledOutline(const Outline& unit, double unit_area, double area_mm2, double center_mm) {
  const double k = std::sqrt(std::max(area_mm2, 0.0) / unit_area);
  Outline o(unit.size());
  for (std::size_t i = 0; i < unit.size(); ++i) o[i] = {center_mm + k * unit[i].x(), k * unit[i].y()};
  return o;
}

BeadDims OutlineDims(const Outline& o) {
  BeadDims d;
  if (o.empty()) return d;
  double lo = o[0].x(), hi = o[0].x();
  for (const auto& p : o) {
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
    d.height_mm = std::max(d.height_mm, p.y());
  }
  d.max_width_mm = hi - lo;
  d.contact_width_mm = o.back().x() - o.front().x();
  return d;
}

}  // namespace bead::sim
