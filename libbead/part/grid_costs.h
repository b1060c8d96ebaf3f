// The registration's costs (part/registration.cc: the truncated cost, the
// same with its gradient and curvature in the shift, where the surfaces
// agree) and the gains' surface below, where the new profile's points lie
// on the grid of the surface below's rows: a sensor's uniform points over
// a layer below scanned by the same sensor. At a shift s every point then
// falls the same fraction of the way between two values of each row, so
// the surface below at the points is two unaligned loads and a blend a
// row, eight points a register (part/part_kernel.h), and no point looks
// anything up. The definitions are registration.cc's, to a float's
// rounding; the few points where one row is known and the other is not
// are sampled one by one (SurfaceGrid::SampleAt).
#pragma once

#include <span>
#include <vector>

#include "libbead/part/part_kernel.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

// The new points on the grid of the surface below.
class PointsOnGrid {
 public:
  // False (and nothing to use) where the surface below's rows are not
  // points on one grid, or the new points do not lie on it.
  bool Make(std::span<const float> x, std::span<const float> z, const SurfaceGrid& below);
  // Whether the last Make succeeded.
  bool Ready() const { return count_ > 0; }
  // The loops' build (part_kernel.h): the one this processor runs unless set.
  void UseKernel(const PartKernel& kernel) { kernel_ = &kernel; }

  // The truncated squared gain over the points with x in [lo, hi], in
  // noise variances (noise2: one point's), each capped at `cap`.
  double TruncatedCost(double s, double noise2, double cap, double lo, double hi) const;
  struct Local {
    double cost = 0.0, gradient = 0.0, curvature = 0.0;
  };
  // The truncated cost over every point, with its gradient and
  // Gauss-Newton curvature in s over the points under the cap.
  Local LocalCost(double s, double noise2, double cap) const;
  // Where the surfaces agree at s (|gain| <= tau): the sum of the squared
  // gains, how many points, and how many of them where the surface below
  // slopes more than feature_slope (registration.cc's Settle).
  struct Agreement {
    double sum_d2 = 0.0;
    int points = 0, features = 0;
  };
  Agreement Agree(double s, double tau, double feature_slope) const;
  // The surface below at each new point (in the points' order), moved by
  // s: NaN where it is not known.
  void BelowAt(double s, std::vector<float>& z_below) const;

 private:
  // At shift s: the rows as the kernel reads them, the lattice indices
  // [begin, end) inside every row, and [any_begin, any_end) inside some.
  struct Span {
    GridRows rows;
    std::ptrdiff_t begin, end, any_begin, any_end;
  };
  Span Inside(double s) const;
  // The points (not NaN) in lattice indices [begin, end).
  std::size_t PointsIn(std::ptrdiff_t begin, std::ptrdiff_t end) const;
  // Calls f(i, sample) for the points in [begin, end) where some row is
  // known but not every one (in [any_begin, any_end), outside [in.begin,
  // in.end)), each sampled one by one.
  template <class F>
  void EachEdgePoint(double s, std::ptrdiff_t begin, std::ptrdiff_t end, const Span& in, F f) const;

  const PartKernel* kernel_ = &ActivePartKernel();
  const SurfaceGrid* grid_ = nullptr;
  const SurfaceRow* rows_[2] = {};
  int count_ = 0;
  bool unit_ = false;  // every row's values measured points, each one point's variance
  double dx_mm_ = 0.0;
  double x0_mm_ = 0.0;                  // x of z_[0]
  std::vector<float> z_;                // the new points on the grid, NaN where none
  std::vector<int> counted_;            // counted_[i]: points before index i
  mutable std::vector<float> on_grid_;  // BelowAt's scratch
};

}  // namespace bead::part
