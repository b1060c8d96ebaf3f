#include "libbead/part/superellipse.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>

namespace bead::part {
namespace {

const std::array<double, SuperellipseTable::kNodes>& Nodes() {
  static const std::array<double, SuperellipseTable::kNodes> u = [] {
    std::array<double, SuperellipseTable::kNodes> v{};
    for (int k = 0; k < SuperellipseTable::kNodes; ++k) v[k] = -1.0 + (k + 0.5) * (2.0 / SuperellipseTable::kNodes);
    return v;
  }();
  return u;
}

// The stadium of corner share c = -p at v = |u| (< 1): flat to 1 - c, a
// quarter ellipse beyond, s = sqrt(1 - w^2) with w = (v - 1 + c) / c; ds/dv
// = -w / (s c), dw/dc = (1 - v) / c^2, and ds/dp = -ds/dc.
SuperellipseTable::Value StadiumAt(double u, double p) {
  const double c = -p, v = std::min(std::abs(u), 1.0 - 1e-12), w = (v - 1.0 + c) / c;
  if (!(w > 0.0)) return {1.0, 0.0, 0.0};
  const double s = std::sqrt(1.0 - w * w), ds_dv = -w / (s * c);
  return {s, u < 0.0 ? -ds_dv : ds_dv, (w / s) * (1.0 - v) / (c * c)};
}

}  // namespace

double SuperellipseS(double u, double p) {
  if (IsStadium(p)) return StadiumAt(u, p).s;
  const double v = std::min(std::abs(u), 1.0 - 1e-12);
  return v == 0.0 ? 1.0 : std::pow(1.0 - std::pow(v, p), 1.0 / p);
}

double ReachAt(double h, double p) {
  h = std::clamp(h, 0.0, 1.0 - 1e-9);
  if (IsStadium(p)) return std::max(0.0, 1.0 + p - p * std::sqrt(1.0 - h * h));
  return std::pow(1.0 - std::pow(h, p), 1.0 / p);
}

SuperellipseTable::Value SuperellipseAt(double u, double p) {
  if (IsStadium(p)) return StadiumAt(u, p);
  const double v = std::min(std::abs(u), 1.0 - 1e-12);
  if (v == 0.0) return {1.0, 0.0, 0.0};
  const double vp = std::pow(v, p), rest = 1.0 - vp, s = std::pow(rest, 1.0 / p);
  // ds/dv = -v^(p-1) s^(1-p); d ln s / dp = -ln(1 - v^p) / p^2 - v^p ln v / (p (1 - v^p)).
  const double ds_dv = -(vp / v) * s / rest;
  const double dlns_dp = -std::log(rest) / (p * p) - vp * std::log(v) / (p * rest);
  return {s, u < 0.0 ? -ds_dv : ds_dv, s * dlns_dp};
}

SuperellipseTable::SuperellipseTable(double p) : p_(p) {
  s_.resize(kEntries + 1), ds_du_.resize(kEntries + 1), ds_dp_.resize(kEntries + 1);
  for (int k = 0; k <= kEntries; ++k) {
    const Value v = SuperellipseAt(k * kTabulatedU / kEntries, p);
    s_[k] = v.s, ds_du_[k] = v.ds_du, ds_dp_[k] = v.ds_dp;
  }
  for (int k = 0; k < kNodes; ++k) {
    const Value v = SuperellipseAt(Nodes()[k], p);
    node_s_[k] = v.s, node_ds_dp_[k] = v.ds_dp;
  }
}

SuperellipseTable::Value SuperellipseTable::At(double u) const {
  int k = 0;
  double t = 0.0;
  Locate(u, k, t);
  return At(k, t, u < 0.0);
}

const std::array<double, SuperellipseTable::kNodes>& SuperellipseTable::node_u() const { return Nodes(); }

const SuperellipseTable& SuperellipseOf(double p) {
  // The grid's tables, each made when first asked for and kept: a free
  // solve holds five of them at once (silhouette_top.cc). (They shared one
  // cache of 32 with the layers' pooled exponents, the oldest let go: from
  // the 13th pool on a grid table could be freed while a solve held it,
  // which crashed a run of the part tests once the pools' exponents moved.)
  const std::vector<double>& grid = GridOf(p);
  thread_local std::vector<std::unique_ptr<SuperellipseTable>> on_grid[2] = {
      std::vector<std::unique_ptr<SuperellipseTable>>(SuperellipseGrid().size()),
      std::vector<std::unique_ptr<SuperellipseTable>>(StadiumGrid().size())};
  if (const auto it = std::find(grid.begin(), grid.end(), p); it != grid.end()) {
    std::unique_ptr<SuperellipseTable>& t = on_grid[IsStadium(p)][static_cast<std::size_t>(it - grid.begin())];
    if (!t) t = std::make_unique<SuperellipseTable>(p);
    return *t;
  }
  // Any other exponent (a layer's pooled one): the last kKept kept, the
  // oldest let go beyond that (no caller holds one while asking for others).
  constexpr std::size_t kKept = 32;
  thread_local std::deque<std::unique_ptr<SuperellipseTable>> others;
  for (const auto& t : others)
    if (t->p() == p) return *t;
  if (others.size() == kKept) others.pop_front();
  others.push_back(std::make_unique<SuperellipseTable>(p));
  return *others.back();
}

const std::vector<double>& SuperellipseGrid() {
  static const std::vector<double> grid = [] {
    std::vector<double> g;
    for (double p = 1.2; p <= 8.0; p *= 1.1) g.push_back(p);
    return g;
  }();
  return grid;
}

const std::vector<double>& StadiumGrid() {
  static const std::vector<double> grid = [] {
    std::vector<double> g;
    for (double c = 0.1; c <= 1.6; c *= 1.1) g.push_back(-c);
    return g;
  }();
  return grid;
}

}  // namespace bead::part
