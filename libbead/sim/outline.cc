#include "libbead/sim/outline.h"

#include <cmath>
#include <numbers>

namespace bead::sim {

double OutlineArea(const Outline& o) {
  double twice = 0.0;
  for (std::size_t i = 0; i < o.size(); ++i) {
    const Eigen::Vector2d& p = o[i];
    const Eigen::Vector2d& q = o[(i + 1) % o.size()];  // the last point closes back along h = 0
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(0.5 * twice);
}

Outline RectangleOutline(double w, double h, double c) {
  return {{c - w / 2, 0.0}, {c - w / 2, h}, {c + w / 2, h}, {c + w / 2, 0.0}};
}

Outline SemicircleOutline(double r, double c, int n) {
  Outline o;
  o.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double a = std::numbers::pi * (1.0 - static_cast<double>(i) / (n - 1));
    o.emplace_back(c + r * std::cos(a), r * std::sin(a));
  }
  o.front().y() = 0.0;
  o.back().y() = 0.0;
  return o;
}

Outline ParabolaOutline(double w, double h, double c, int n) {
  Outline o;
  o.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double u = -1.0 + 2.0 * i / (n - 1);
    o.emplace_back(c + u * w / 2, h * (1.0 - u * u));
  }
  return o;
}

Outline TrapezoidOutline(double b, double t, double h, double c) {
  return {{c - b / 2, 0.0}, {c - t / 2, h}, {c + t / 2, h}, {c + b / 2, 0.0}};
}

}  // namespace bead::sim
