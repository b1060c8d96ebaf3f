// The twin's surfaces across a part (bed frame, on a fine truth grid) and
// how a bead is laid on one: an ellipse (or a superellipse) sunk into the
// surface before it until its material is the bead's area.
#pragma once

#include <algorithm>
#include <vector>

namespace bead::sim {

inline constexpr double kGridMm = 0.01;  // the truth's surfaces are held this finely ...

// ... or a fifth of the sensor's point spacing where that is finer (a glue
// bead 0.6 mm wide seen at 5 um: on a 0.01 mm grid the sensor saw the
// chords beside the ellipse's sides, and its fitted shapes came out 0.5 %
// small).
inline double TruthGridMm(double point_spacing_mm) { return std::min(kGridMm, 0.2 * point_spacing_mm); }

struct Surface {
  double x0 = 0.0;
  double dx = kGridMm;  // between values of z
  std::vector<double> z;
  double At(double x) const {
    const double u = std::clamp((x - x0) / dx, 0.0, static_cast<double>(z.size() - 1));
    const std::size_t k = std::min(static_cast<std::size_t>(u), z.size() - 2);
    return z[k] + (u - static_cast<double>(k)) * (z[k + 1] - z[k]);
  }
};

struct Layer {
  double area = 0.0, center = 0.0;
};

// Lays `layer`'s ellipse (half-width a, half-height b) on `below` and
// returns the top envelope the sensor sees; *zc: the ellipse's centre
// height where it settled. fill_under: the material fills down to the
// surface below wherever the ellipse's top stands over it (a road that
// leaves no void under its sides: nothing hidden from above); else only the
// ellipse is material (an overhanging bead hides the groove under it).
// exponent: the bead a superellipse |u|^p + |v|^p = 1 (2: the ellipse).
Surface Lay(const Surface& below, const Layer& layer, double a, double b, double* zc = nullptr, bool fill_under = false,
            double exponent = 2.0);

}  // namespace bead::sim
