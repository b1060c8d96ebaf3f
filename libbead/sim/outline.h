// Bead outlines: the boundary of a bead cross-section in the wheel frame
// (s across the wheel surface, h up from it, mm), listed from the left
// contact point over the top to the right contact point. The surface h = 0
// closes it. Curved shapes are dense polygons; their exact areas are given
// in closed form beside them, for tests and truth files.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace bead::sim {

using Outline = std::vector<Eigen::Vector2d>;

// Area enclosed between the outline and the surface (shoelace formula).
double OutlineArea(const Outline& outline);

// A w x h rectangle centred on s = center.          area = w * h
Outline RectangleOutline(double width_mm, double height_mm, double center_mm = 0.0);
// A half disc of radius r standing on its diameter.  area = pi r^2 / 2
Outline SemicircleOutline(double radius_mm, double center_mm = 0.0, int vertices = 2001);
// h(s) = H (1 - (2 (s - c) / W)^2).                  area = 2 W H / 3
Outline ParabolaOutline(double width_mm, double height_mm, double center_mm = 0.0, int vertices = 2001);
// Bottom b, top t, height H.                          area = (b + t) H / 2
Outline TrapezoidOutline(double bottom_mm, double top_mm, double height_mm, double center_mm = 0.0);

}  // namespace bead::sim
