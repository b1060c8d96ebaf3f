// StreamingFlow: the flow of flow.h on-line, for acquisition software. Log
// samples and profile geometries go in as they arrive; flow samples come
// out once everything they depend on has arrived, in profile order:
//  - the wheel speed at a log sample needs the Savitzky-Golay window and
//    the Hampel window after it: speed_window_s / 2 + speed_hampel_s;
//  - a profile's area needs area_hampel_half profiles after it;
//  - its extrusion time lies in the past, so the log already holds it.
// The delay is therefore bounded by max(speed_window_s / 2 + speed_hampel_s,
// area_hampel_half / profile rate) plus one log sample (the missed-read check).
// The arithmetic is the batch's, from the run's first profile to its last
// (the speed's last window is fitted at Finish as the batch's interp mode
// fits it), occlusion bias and uncertainty included: identical to rounding
// (tested). Differences, by design: encoder glitches use the fixed
// threshold min_glitch_counts (the batch can also raise it from the whole
// run's noise); unless area_sigma_floor_mm2 is given, the area Hampel's
// floor is the running median of the sigmas seen so far, refreshed as
// their count doubles (the batch's is the whole run's); the log step is
// 1 / log_rate_hz (the batch's the median step); the optional area
// smoothing is batch-only; an extrusion time older than history_s is NaN.
// Memory is bounded and reserved at construction: it keeps history_s of
// log (about 20 kB per second at 500 Hz; the extrusion time of a profile
// must lie within it: the nozzle-to-laser travel at the slowest wheel
// speed), at least 1024 profiles' areas and the last 8192 area sigmas for the
// floor's median. Once the log's first Savitzky-Golay window is in, no
// call allocates, Finish included (tested), so long as finished samples
// are popped.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/flow/flow.h"
#include "libbead/series/encoder.h"

namespace bead {

// What an off-line pass knows of the whole log before streaming it
// (archive/streamed_flow.h): with these, and the area floor given in
// FlowOptions, the stream is the batch bit for bit.
struct WholeLogFacts {
  double step_s;         // the median step, as the batch's
  double glitch_counts;  // the batch's threshold: max(min_glitch_counts, 8 robust sigmas)
};

class StreamingFlow {
 public:
  // `log_rate_hz` fixes the Savitzky-Golay window in samples, as the batch
  // derives it from the log's median step.
  StreamingFlow(const Rig& rig, const FlowOptions& options, double log_rate_hz, double history_s = 600.0);
  StreamingFlow(const Rig& rig, const FlowOptions& options, const WholeLogFacts& log, double history_s = 600.0);

  void PushLog(double t_s, int64_t raw_encoder, double screw_rpm);
  // `area_corrected_mm2` and its standard uncertainty: the occlusion
  // stage's (NaN: none ran; the measured area is taken, its sigma NaN).
  void PushProfile(double t_s, int64_t raw_encoder, const BeadGeometry& geometry,
                   double area_corrected_mm2 = std::numeric_limits<double>::quiet_NaN(),
                   double area_corrected_sigma_mm2 = std::numeric_limits<double>::quiet_NaN());
  // The next finished flow sample, if any.
  bool Pop(FlowSample& out);
  // No more input: finish what can be finished with truncated windows.
  void Finish();

  // So far: encoder reads repaired, speed and area samples the Hampel
  // filters replaced (as FlowResult's), the range of the repaired encoder
  // positions, and extrusion times not found once older log had been let
  // go (the batch, holding the whole log, might have found them).
  int encoder_repairs() const { return encoder_repairs_; }
  int speed_outliers() const { return speed_outliers_; }
  int area_outliers() const { return area_outliers_; }
  double counts_min() const { return counts_min_; }
  double counts_max() const { return counts_max_; }
  std::size_t history_misses() const { return history_misses_; }

 private:
  void ProcessLog();
  void ProcessProfiles();
  void CompactLog();
  void CompactProfiles();

  Rig rig_;
  FlowOptions options_;
  double dt_, glitch_counts_;
  int sg_half_, hampel_half_;
  std::vector<double> sg_weights_, sg_tail_weights_;  // tail: sg_half_ rows of the window's length
  EncoderUnwrapper unwrapper_;
  // Log history (unwrapped counts; repaired one sample late).
  std::vector<double> t_, counts_, rpm_, speed_raw_, speed_;
  std::vector<int64_t> raw_;
  std::size_t repaired_upto_ = 0;  // samples [0, repaired_upto_) are final positions
  std::size_t speed_raw_upto_ = 0, speed_upto_ = 0;
  // Profiles waiting for their area window and their speed.
  struct Pending {
    int64_t index;
    double t_s;
    int64_t raw;
    double area, area_c, area_c_sigma;
  };
  std::vector<Pending> profiles_;  // waiting from profiles_head_ on
  std::size_t profiles_head_ = 0;
  std::vector<double> area_window_, area_c_window_, area_sigmas_;
  std::size_t area_base_ = 0;   // the profile index of area_window_[0]
  double running_floor_ = 0.0;  // median of area_sigmas_ when floor_count_ had been seen
  std::size_t floor_count_ = 0, sigmas_seen_ = 0;
  std::size_t next_profile_ = 0;
  std::vector<FlowSample> ready_;  // finished from ready_head_ on
  std::size_t ready_head_ = 0;
  std::size_t log_keep_ = 0;  // samples of log history kept (at least)
  std::vector<double> scratch_, floor_scratch_;
  bool finished_ = false;
  int encoder_repairs_ = 0, speed_outliers_ = 0, area_outliers_ = 0;
  double counts_min_ = std::numeric_limits<double>::infinity(), counts_max_ = -counts_min_;
  std::size_t ranged_upto_ = 0;  // samples [0, ranged_upto_) in counts_min_ / counts_max_
  std::size_t log_dropped_ = 0, history_misses_ = 0;
};

}  // namespace bead
