// Wheel encoder: raw counter -> continuous position in counts, growing as
// the surface moves from the nozzle to the laser.
//  - wrap: the counter wraps modulo 2^bits; each step is taken as the
//    signed difference modulo 2^bits (the wheel never turns half the
//    counter range between two reads);
//  - direction: -1 flips the sign so positions grow nozzle -> laser;
//  - missed reads: a repeated value while both neighbours move the same
//    way is a read the acquisition missed; it is replaced by interpolation
//    in time;
//  - glitches: a single value off the line through its neighbours by more
//    than max(min_glitch_counts, 8 robust sigmas of the second difference)
//    is replaced the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "libbead/core/rig.h"

namespace bead {

struct EncoderTrack {
  std::vector<double> counts;     // unwrapped, repaired position
  std::vector<uint8_t> repaired;  // 1: missed read or glitch, replaced
  int missed_reads = 0;
  int glitches = 0;
};

struct EncoderOptions {
  double min_glitch_counts = 50.0;
};

// The repair rule for sample i (0 < i < n - 1) of unwrapped `counts`: a
// missed read or a glitch returns kMissedRead / kGlitch and sets
// `*repaired` to the value interpolated in time; otherwise kNone. Batch and
// streaming paths both use it.
enum class EncoderRepair { kNone, kMissedRead, kGlitch };
EncoderRepair RepairEncoderSample(const double* counts, const int64_t* raw, const double* t_s, std::size_t i,
                                  double glitch_counts, double* repaired);

// `t_s` (same length) places the interpolation in time; empty: even steps.
EncoderTrack UnwrapEncoder(const std::vector<int64_t>& raw, const EncoderSpec& spec,
                           const std::vector<double>& t_s = {}, const EncoderOptions& options = {});

// Unwrapped counts to wheel angle (rad) and to surface travel (mm, the
// rig's wheel diameter).
double CountsToAngleRad(double counts, const EncoderSpec& spec);
double CountsToMm(double counts, const Rig& rig);

// The unwrapped value of `raw` nearest to `near_counts` (positions of
// another series of the same counter, e.g. the profiles against the log).
double UnwrapNear(int64_t raw, const EncoderSpec& spec, double near_counts);

// The raw counter that reads a given unwrapped position.
int64_t RawFromCounts(double counts, const EncoderSpec& spec);

// Streaming: one raw value at a time, no look-ahead (no repair).
class EncoderUnwrapper {
 public:
  explicit EncoderUnwrapper(const EncoderSpec& spec) : spec_(spec) {}
  double Push(int64_t raw);

 private:
  EncoderSpec spec_;
  bool started_ = false;
  int64_t last_raw_ = 0;
  double position_ = 0.0;
};

}  // namespace bead
