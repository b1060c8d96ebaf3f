// The shape a wall's bead is taken to have (part/hidden_groove.h): a
// superellipse |u|^p + |v|^p = 1 (u = (x - x0) / a across, v = (z - z0) / b
// up), whose half height at u is b s(u), s = (1 - |u|^p)^(1/p). p = 2 is the
// ellipse; above 2 the top flattens and the sides steepen toward a box,
// below it the bead narrows toward a diamond (the family the roads' overlap
// model shares: part/road_arcs.h). The exponent matters to the groove an
// overhanging bead hides: the lower outline is not seen, and with the ends
// and the top's height held, a box hides more under its sides than an
// ellipse, a diamond less. An ellipse taken for a superellipse of p = 2.5
// (or 1.6) corrected an independently generated wall's area by -25 % (+17 %).
//
// s is tabulated once per exponent: over |u| <= kTabulatedU (the top's points
// the silhouette solves over) with its derivatives in |u| and in p, and
// exactly at the groove's nodes. Linear between entries, s is off by at most
// 6e-6 for 2 <= p <= 8 and 3e-5 at p = 1.2 (near u = 0, where its
// curvature is unbounded below p = 2): times b, nanometres, a thousandth of
// a profiler's noise.
//
// A second family, the stadium, is held in the same tables under negative
// exponents: p = -c is a flat top over |u| <= 1 - c with a quarter ellipse
// of semi-axes c a across and b up at each end, s = sqrt(1 - w^2), w =
// (|u| - 1 + c) / c. c = 1 is the ellipse, c -> 0 a box; c = b / a gives
// half circles for ends: large-scale printing's tamped bead, a flat top and
// bottom held at the layer height with rounded sides (no superellipse has
// its top: a layer's pooled one missed it by 8-14 % of its height). Above
// c = 1 the ends' arcs meet at a ridge over the centre (the grid's far
// side of the ellipse, for its neighbours).
#pragma once

#include <algorithm>
#include <array>
#include <vector>

namespace bead::part {

class SuperellipseTable {
 public:
  static constexpr double kTabulatedU = 0.9;
  static constexpr int kEntries = 512;
  // The groove's midpoint nodes across the bead (u_k = -1 + (k + 1/2) 2 /
  // kNodes; the same for every exponent).
  static constexpr int kNodes = 200;

  explicit SuperellipseTable(double p);
  double p() const { return p_; }

  struct Value {
    double s, ds_du, ds_dp;  // s at u, its derivative in u and in p
  };
  // At |u| <= kTabulatedU (beyond it: the last entry's).
  Value At(double u) const;
  // Where |u| falls between the entries: entry k and the fraction t of the
  // way to k + 1 (the same for every exponent: found once for many); s
  // alone there, and all three (u's sign given).
  static void Locate(double u, int& k, double& t) {
    const double f = std::min(u < 0.0 ? -u : u, kTabulatedU) * (kEntries / kTabulatedU);
    k = std::min(static_cast<int>(f), kEntries - 1);
    t = f - k;
  }
  double S(int k, double t) const { return s_[k] + t * (s_[k + 1] - s_[k]); }
  // s at the kEntries + 1 entries.
  const double* entries() const { return s_.data(); }
  Value At(int k, double t, bool negative) const {
    const double slope = ds_du_[k] + t * (ds_du_[k + 1] - ds_du_[k]);
    return {S(k, t), negative ? -slope : slope, ds_dp_[k] + t * (ds_dp_[k + 1] - ds_dp_[k])};
  }

  // The nodes: u_k, s(u_k) and ds/dp there.
  const std::array<double, kNodes>& node_u() const;
  const std::array<double, kNodes>& node_s() const { return node_s_; }
  const std::array<double, kNodes>& node_ds_dp() const { return node_ds_dp_; }

 private:
  double p_;
  std::vector<double> s_, ds_du_, ds_dp_;  // at |u| = k kTabulatedU / kEntries
  std::array<double, kNodes> node_s_{}, node_ds_dp_{};
};

// Whether p is a stadium's (its corner share c = -p), not a superellipse's.
inline bool IsStadium(double p) { return p < 0.0; }
// The ellipse's own value of p's family (2, or -1 for the stadium's).
inline double EllipseOf(double p) { return IsStadium(p) ? -1.0 : 2.0; }

// s and its derivatives exactly (|u| < 1).
SuperellipseTable::Value SuperellipseAt(double u, double p);
// s alone, as SuperellipseAt computes it (without its derivatives' logs).
double SuperellipseS(double u, double p);

// The table of exponent p, made once per thread and exponent: the grid's
// kept (a free solve holds five at once), any other's among the last few
// asked for (a layer holds one exponent).
const SuperellipseTable& SuperellipseOf(double p);

// The exponents a free placement tries (part/silhouette.h): from 1.2 (near
// a diamond) to 8 (near a box), each a tenth above the one before.
const std::vector<double>& SuperellipseGrid();
// The stadiums it tries: c from 0.1 (near a box) to 1.59 (a ridged arch),
// each a tenth above the one before, as p = -c.
const std::vector<double>& StadiumGrid();
// The grid p's family is tried on.
inline const std::vector<double>& GridOf(double p) { return IsStadium(p) ? StadiumGrid() : SuperellipseGrid(); }
// |u| at which the top of p stands a share h of its half-height b over its
// centre (h held to [0, 1)): (1 - h^p)^(1/p); a stadium's 1 - c + c sqrt(1
// - h^2) (at least 0).
double ReachAt(double h, double p);

}  // namespace bead::part
