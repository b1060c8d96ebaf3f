#include "libbead/occlusion/shape_models.h"

#include <cmath>
#include <functional>

namespace bead::occlusion {
namespace {

// Adaptive Simpson on [lo, hi] to an absolute tolerance.
double Simpson(const std::function<double(double)>& f, double lo, double hi, double fl, double fm, double fh,
               double whole, double tol, int depth) {
  const double mid = 0.5 * (lo + hi);
  const double lm = 0.5 * (lo + mid), rm = 0.5 * (mid + hi);
  const double flm = f(lm), frm = f(rm);
  const double left = (mid - lo) / 6 * (fl + 4 * flm + fm), right = (hi - mid) / 6 * (fm + 4 * frm + fh);
  if (depth <= 0 || std::abs(left + right - whole) <= 15 * tol) return left + right + (left + right - whole) / 15;
  return Simpson(f, lo, mid, fl, flm, fm, left, tol / 2, depth - 1) +
         Simpson(f, mid, hi, fm, frm, fh, right, tol / 2, depth - 1);
}

double Integrate(const std::function<double(double)>& f, double lo, double hi) {
  if (!(hi > lo)) return 0.0;
  const double fl = f(lo), fh = f(hi), fm = f(0.5 * (lo + hi));
  return Simpson(f, lo, hi, fl, fm, fh, (hi - lo) / 6 * (fl + 4 * fm + fh), 1e-13, 40);
}

}  // namespace

double CutSuperellipse::TopArea() const {
  // Half the superellipse: 4 a b G(1 + 1/n)^2 / G(1 + 2/n) / 2.
  return 2 * a * b * std::tgamma(1 + 1 / n) * std::tgamma(1 + 1 / n) / std::tgamma(1 + 2 / n);
}

double CutSuperellipse::BottomArea(double nb) const {
  // 2 a b * integral_0^(c/b) (1 - t^nb)^(1/nb) dt.
  const double tau = std::min(c / b, 1.0);
  return 2 * a * b * Integrate([nb](double t) { return std::pow(1 - std::pow(t, nb), 1 / nb); }, 0.0, tau);
}

double CutSuperellipse::ContactWidth() const {
  const double tau = std::min(c / b, 1.0);
  return 2 * a * std::pow(1 - std::pow(tau, n), 1 / n);
}

double FanShadowArea(double c, double x_left, double x_right, double x_origin, double z_origin) {
  const double tan_r = (x_right - x_origin) / (z_origin - c);
  const double tan_l = (x_left - x_origin) / (z_origin - c);
  return c * c * (tan_r - tan_l) / 2;
}

}  // namespace bead::occlusion
