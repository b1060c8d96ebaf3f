// Bead cross-section families, in the bead's own frame: u across the
// surface from the bead's centre, h up from the surface (mm). Each gives
//  - Envelope(u): the height a sensor looking straight down sees, templated
//    on the scalar so Ceres can differentiate it (it drops vertically where
//    the shape is widest: what lies under that is not seen);
//  - TrueArea, VisibleArea: closed form or exact quadrature (double);
//  - whether its hidden part is constrained by what is seen.
// Parameter order is the order of the fields. Sources: the undercut and
// rounded corners of the bead characterisation system thesis (large-scale AM extruder dynamics) 4.4.3 (Fig. 37).
#pragma once

#include <cmath>
#include <numbers>

namespace bead::occlusion {

// |u/a|^n + |(h - c)/b|^n <= 1, h >= 0: a superellipse whose widest point
// stands c above the surface, so it bulges over its contact line (undercut
// 0 < c < b). Its hidden part is fixed by its visible part: the shape is
// symmetric about its widest point.
struct CutSuperellipse {
  static constexpr int kParams = 4;  // a, b, c, n (the centre is fitted beside)
  double a = 1, b = 1, c = 0, n = 2;

  template <typename T>
  static T Envelope(const T* p, const T& u) {
    using std::abs, std::exp, std::log;  // for T = double; Ceres' Jets find theirs by ADL
    const T& a = p[0];
    const T& b = p[1];
    const T& c = p[2];
    const T& n = p[3];
    const T x = abs(u) / a;
    if (!(x < T(1.0))) return T(0.0);
    // (1 - x^n)^(1/n), with x^n computed as exp(n log x) (x > 0).
    const T xn = x > T(1e-12) ? exp(n * log(x)) : T(0.0);
    return c + b * exp(log(T(1.0) - xn) / n);
  }
  double Height() const { return c + b; }
  double TrueArea() const { return TopArea() + BottomArea(n); }
  // Below the widest point, were that part's exponent n_bottom (the seen
  // top says nothing about it: the fit assumes n_bottom = n).
  double BottomArea(double n_bottom) const;
  double VisibleArea() const { return TopArea() + 2 * a * c; }  // straight above
  double ContactWidth() const;
  double TopArea() const;  // the half above the widest point: 2 a b G(1+1/n)^2 / G(1+2/n)
};

// A w x H rectangle with top corners of radius rt and bottom corners of
// radius rb curling in under its widest point (rb is not seen from above:
// its hidden area 2 (1 - pi/4) rb^2 is not constrained by the data).
struct RoundedRectangle {
  static constexpr int kParams = 3;  // w, H, rt
  double w = 1, height = 1, rt = 0, rb = 0;

  template <typename T>
  static T Envelope(const T* p, const T& u) {
    using std::abs, std::sqrt;  // for T = double; Ceres' Jets find theirs by ADL
    const T& w = p[0];
    const T& H = p[1];
    const T& rt = p[2];
    const T x = abs(u);
    if (!(x < w / T(2.0))) return T(0.0);
    const T inner = w / T(2.0) - rt;
    if (x <= inner) return H;
    const T d = x - inner;
    const T r2 = rt * rt - d * d;
    return H - rt + (r2 > T(0.0) ? sqrt(r2) : T(0.0));
  }
  double TrueArea() const { return w * height - (1 - std::numbers::pi / 4) * 2 * (rt * rt + rb * rb); }
  double VisibleArea() const { return w * height - (1 - std::numbers::pi / 4) * 2 * rt * rt; }
};

// h = H (1 - (2u / w)^2): no undercut, nothing hidden from above.
struct ParabolicCap {
  static constexpr int kParams = 2;  // w, H
  double w = 1, height = 1;

  template <typename T>
  static T Envelope(const T* p, const T& u) {
    const T q = T(2.0) * u / p[0];  // (no abs needed: squared)
    return q * q < T(1.0) ? p[1] * (T(1.0) - q * q) : T(0.0);
  }
  double TrueArea() const { return 2.0 * w * height / 3.0; }
  double VisibleArea() const { return TrueArea(); }
};

// Area of the fan's shadows: a sensor whose rays come from `origin` sees
// the bead's widest points at heights c, at x_left and x_right (sensor x,
// origin height z_origin above the surface); below them it sees along the
// rays, not straight down. Returns what that adds to the straight-down
// visible area: c^2 (tan(alpha_right) - tan(alpha_left)) / 2, each tangent
// (x - x_origin) / (z_origin - c). It leaves out the sliver between the
// grazing ray and the shape just above its widest point (for the twin's
// default bead under the fan about 0.04 % of its area).
double FanShadowArea(double c, double x_left, double x_right, double x_origin, double z_origin);

}  // namespace bead::occlusion
