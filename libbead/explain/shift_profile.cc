#include "libbead/explain/shift_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kChi2_1_95 = 3.841;

// Each grid shift's residual with everything else refitted, from the
// middle (the rig file's offset) outward.
std::vector<std::vector<double>> ProfiledResiduals(const SeriesData& d, const EffectSet& current,
                                                   const std::vector<double>& grid,
                                                   const std::vector<std::size_t>& rows, std::size_t mid,
                                                   std::vector<EffectSet>& refits) {
  EffectSet start;
  for (const Active& a : current)
    if (a.effect.kind != Effect::Kind::kPositionShift) start.push_back(a);
  std::vector<std::vector<double>> residuals(grid.size());
  refits.assign(grid.size(), {});
  for (int dir : {+1, -1}) {
    EffectSet walking = start;
    for (long k = static_cast<long>(mid); k >= 0 && k < static_cast<long>(grid.size()); k += dir) {
      if (dir < 0 && k == static_cast<long>(mid)) continue;
      const double g = grid[static_cast<std::size_t>(k)];
      SeriesData held = d;
      const auto hook = d.shifted;
      held.shifted = [hook, g](double counts, const std::vector<double>& delay, std::vector<double>& y,
                               std::vector<double>& base) { hook(counts + g, delay, y, base); };
      Refine(held, walking, rows, 10);
      residuals[static_cast<std::size_t>(k)] = Residual(held, walking);
      refits[static_cast<std::size_t>(k)] = walking;
    }
  }
  return residuals;
}

// The samples every shift keeps (a shift pushes some out of the record
// at its ends, and those need not fit like the rest).
std::vector<std::size_t> CommonRows(const std::vector<std::vector<double>>& residuals,
                                    const std::vector<std::size_t>& rows) {
  std::vector<std::size_t> common;
  for (std::size_t i : rows)
    if (std::all_of(residuals.begin(), residuals.end(),
                    [i](const std::vector<double>& r) { return std::isfinite(r[i]); }))
      common.push_back(i);
  if (common.size() < rows.size() / 2) common = rows;  // too few in common: each its own, scaled
  return common;
}

// The outermost grid crossings of `limit` (a flat profile with the refits'
// own scatter on it is not cut short at its first bump).
void GridInterval(ShiftProfile& p, std::size_t ib, double limit) {
  std::size_t a = ib, b = ib;
  for (std::size_t k = 0; k < p.sse.size(); ++k)
    if (p.sse[k] <= limit) a = std::min(a, k), b = std::max(b, k);
  auto cross = [&](std::size_t inside, std::size_t outside) {
    const double s0 = p.sse[inside], s1 = p.sse[outside];
    const double f = s1 > s0 ? std::clamp((limit - s0) / (s1 - s0), 0.0, 1.0) : 0.0;
    return p.shift_counts[inside] + f * (p.shift_counts[outside] - p.shift_counts[inside]);
  };
  p.lo_at_edge = a == 0;
  p.hi_at_edge = b + 1 == p.sse.size();
  p.lo = p.lo_at_edge ? p.shift_counts.front() : cross(a, a - 1);
  p.hi = p.hi_at_edge ? p.shift_counts.back() : cross(b, b + 1);
}

}  // namespace

ShiftProfile ProfileShift(const SeriesData& d, const EffectSet& current, const Effect& shift_effect,
                          const std::vector<std::size_t>& rows) {
  ShiftProfile p;
  const std::vector<double>& grid = shift_effect.grid[0];
  p.shift_counts = grid;
  const std::size_t mid = static_cast<std::size_t>(
      std::min_element(grid.begin(), grid.end(), [](double a, double b) { return std::abs(a) < std::abs(b); }) -
      grid.begin());
  std::vector<EffectSet> refits;
  const auto residuals = ProfiledResiduals(d, current, grid, rows, mid, refits);
  const std::vector<std::size_t> common = CommonRows(residuals, rows);
  double best_sse = kInf;
  std::size_t ib = 0;
  for (std::size_t k = 0; k < residuals.size(); ++k) {
    p.sse.push_back(Sse(residuals[k], common));
    if (p.sse.back() < best_sse) best_sse = p.sse.back(), ib = k;
  }
  p.best = grid[ib];
  p.best_index = ib;
  p.refit_at_best = refits[ib];
  p.s_min = best_sse;
  // Between grid points: the parabola through the lowest three.
  if (ib > 0 && ib + 1 < grid.size()) {
    const double h = grid[ib + 1] - grid[ib];
    const double sm = p.sse[ib - 1], s0 = p.sse[ib], sp = p.sse[ib + 1];
    const double curvature = sm - 2 * s0 + sp;
    if (curvature > 0) {
      const double step = std::clamp(h * (sm - sp) / (2 * curvature), -h, h);
      p.curvature = curvature / (2 * h * h);
      p.best = grid[ib] + step;
      p.s_min = s0 - p.curvature * step * step;
    }
  }
  p.lo = p.hi = p.best;
  return p;
}

void ShiftInterval(ShiftProfile& p, double q) {
  p.q = q;
  const double delta = kChi2_1_95 * (std::isfinite(q) ? q : 0.0);
  const std::size_t ib = p.best_index;
  if (p.curvature > 0) {
    const double half = std::sqrt(delta / p.curvature);
    if (half <= p.shift_counts[ib + 1] - p.shift_counts[ib]) {  // within the parabola's reach
      p.lo = p.best - half, p.hi = p.best + half;
      p.lo_at_edge = p.hi_at_edge = false;
      return;
    }
  }
  GridInterval(p, ib, p.s_min + delta);
  p.lo = std::min(p.lo, p.best);
  p.hi = std::max(p.hi, p.best);
}

}  // namespace bead::explain
