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
  // block of kBlock segments and in each span of kSpan, so that Find
  // passes over spans and blocks that never reach the target instead of
  // walking their segments (the same answer, bit for bit; a travel of N
  // log samples in N / kSpan + 2 (kSpan / kBlock + kBlock) steps).
  void BuildIndex();
  static constexpr std::size_t kBlock = 8, kSpan = 8 * kBlock;

  // Latest t_e <= t_measured_s with p(t_e) = target_counts; NaN when the
  // wheel never stood there before (material laid before the log started).
  double Find(double t_measured_s, double target_counts) const { return Find(StartAt(t_measured_s), target_counts); }

  // Where a search from t_measured_s starts: the log segment holding it
  // (j = 0: before the log) and the position there. For one profile
  // searched for many targets (explain tries many offsets), made once.
  struct Start {
    std::size_t j = 0;
    double t_s = 0.0, counts = 0.0;
  };
  Start StartAt(double t_measured_s) const;
  double Find(const Start& from, double target_counts) const;

  // p(t) by linear interpolation (clamped at the ends).
  double PositionAt(double t_s) const;

 private:
  const std::vector<double>& t_;
  const std::vector<double>& p_;
  std::vector<double> block_min_, block_max_;  // samples [b kBlock, (b + 1) kBlock] of full blocks
  std::vector<double> span_min_, span_max_;    // samples [s kSpan, (s + 1) kSpan] of full spans
};

}  // namespace bead
