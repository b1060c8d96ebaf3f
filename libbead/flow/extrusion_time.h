// Extrusion time (thesis 3.1.2, Table 2): the material under the laser at
// a profile left the nozzle when the wheel stood `offset` counts earlier.
// Given the log's unwrapped positions p(t), find the time t_e with
// p(t_e) = p_profile - offset by linear interpolation between the two log
// samples that bracket it.
//
// Done right where Table 2's look-ahead is not: positions are unwrapped
// (counter wrap), and the search runs backward from the profile's time to
// the latest crossing before it, so a wheel that stopped (flat p) or ran
// backward (p not monotonic) gives the last time the nozzle stood over
// that part of the surface.
#pragma once

#include <cstddef>
#include <vector>

namespace bead {

class ExtrusionTimeFinder {
 public:
  // log positions must be finite; times increasing. Cheap to make (no
  // copy, no allocation): StreamingFlow makes one per profile.
  ExtrusionTimeFinder(const std::vector<double>& log_t_s, const std::vector<double>& log_counts);

  // For many searches over one long log: the range of positions in each
  // block of kBlock segments, so that Find passes over blocks that never
  // reach the target instead of walking their segments (the same answer,
  // bit for bit; a travel of N log samples in N / kBlock + 2 kBlock steps).
  void BuildIndex();
  static constexpr std::size_t kBlock = 64;

  // Latest t_e <= t_measured_s with p(t_e) = target_counts; NaN when the
  // wheel never stood there before (material laid before the log started).
  double Find(double t_measured_s, double target_counts) const;

  // p(t) by linear interpolation (clamped at the ends).
  double PositionAt(double t_s) const;

 private:
  const std::vector<double>& t_;
  const std::vector<double>& p_;
  std::vector<double> block_min_, block_max_;  // samples [b kBlock, (b + 1) kBlock] of full blocks
};

}  // namespace bead
