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

}  // namespace

SuperellipseTable::Value SuperellipseAt(double u, double p) {
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
  // The grid's tables and a layer's pooled exponent or two; the oldest let
  // go beyond that.
  constexpr std::size_t kKept = 32;
  thread_local std::deque<std::unique_ptr<SuperellipseTable>> tables;
  for (const auto& t : tables)
    if (t->p() == p) return *t;
  if (tables.size() == kKept) tables.pop_front();
  tables.push_back(std::make_unique<SuperellipseTable>(p));
  return *tables.back();
}

const std::vector<double>& SuperellipseGrid() {
  static const std::vector<double> grid = [] {
    std::vector<double> g;
    for (double p = 1.2; p <= 8.0; p *= 1.1) g.push_back(p);
    return g;
  }();
  return grid;
}

}  // namespace bead::part
