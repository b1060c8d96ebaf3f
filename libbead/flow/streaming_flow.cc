#include "libbead/flow/streaming_flow.h"

#include <algorithm>
#include <cmath>

#include "libbead/flow/extrusion_time.h"
#include "libbead/core/median.h"
#include "libbead/series/hampel.h"
#include "libbead/series/interpolate.h"
#include "libbead/series/savgol.h"

namespace bead {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

StreamingFlow::StreamingFlow(const Rig& rig, const FlowOptions& options, double log_rate_hz)
    : rig_(rig), options_(options), dt_(1.0 / log_rate_hz), unwrapper_(rig.encoder) {
  const int window = SpeedWindowSamples(options, dt_);
  sg_half_ = window / 2;
  sg_weights_ = SavgolWeights(window, std::min(options.speed_order, window - 1), 1, dt_, sg_half_);
  hampel_half_ = std::max(1, static_cast<int>(std::lround(options.speed_hampel_s / dt_)));
}

void StreamingFlow::PushLog(double t_s, int64_t raw, double screw_rpm) {
  t_.push_back(t_s);
  raw_.push_back(raw);
  counts_.push_back(unwrapper_.Push(raw));
  rpm_.push_back(screw_rpm);
  ProcessLog();
  ProcessProfiles();
}

void StreamingFlow::PushProfile(double t_s, int64_t raw, const BeadGeometry& g, double area_c) {
  const double a = g.valid() ? g.area_mm2 : (g.status == ProfileStatus::kNoBead ? 0.0 : kNaN);
  profiles_.push_back({static_cast<int64_t>(next_profile_++), t_s, raw, a, g.valid() && !std::isnan(area_c) ? area_c : a});
  area_window_.push_back(a);
  if (g.valid() && std::isfinite(g.area_sigma_mm2)) area_sigmas_.push_back(g.area_sigma_mm2);
  area_c_window_.push_back(profiles_.back().area_c);
  ProcessProfiles();
}

void StreamingFlow::ProcessLog() {
  const std::size_t n = t_.size();
  // Missed reads and glitches, one sample late (the batch's rule at the fixed threshold).
  while (repaired_upto_ + 1 < n) {
    const std::size_t i = repaired_upto_;
    double value = 0.0;
    if (i >= 1 && RepairEncoderSample(counts_.data(), raw_.data(), t_.data(), i, EncoderOptions{}.min_glitch_counts,
                                      &value) != EncoderRepair::kNone)
      counts_[i] = value;
    ++repaired_upto_;
  }
  // Speed by the Savitzky-Golay derivative once its window is final.
  speed_raw_.resize(n, kNaN);
  const std::size_t w = sg_weights_.size();
  while (speed_raw_upto_ + sg_half_ < repaired_upto_ && speed_raw_upto_ >= static_cast<std::size_t>(sg_half_)) {
    double acc = 0.0;
    for (std::size_t j = 0; j < w; ++j) acc += sg_weights_[j] * counts_[speed_raw_upto_ - sg_half_ + j];
    speed_raw_[speed_raw_upto_++] = acc;
  }
  if (speed_raw_upto_ < static_cast<std::size_t>(sg_half_)) {
    // The run's first samples: the interp edge fit, once a whole window is in.
    if (repaired_upto_ >= w) {
      for (std::size_t p = 0; p < static_cast<std::size_t>(sg_half_); ++p) {
        const auto head = SavgolWeights(static_cast<int>(w), std::min(options_.speed_order, static_cast<int>(w) - 1), 1,
                                        dt_, static_cast<double>(p));
        double acc = 0.0;
        for (std::size_t j = 0; j < w; ++j) acc += head[j] * counts_[j];
        speed_raw_[p] = acc;
      }
      speed_raw_upto_ = sg_half_;
    }
  }
  // Hampel on the speed once its window is final.
  speed_.resize(n, kNaN);
  std::vector<double> scratch;
  const double mpc = rig_.MmPerCount();
  while (speed_upto_ + hampel_half_ < speed_raw_upto_ || (finished_ && speed_upto_ < speed_raw_upto_)) {
    bool out = false;
    const double v = HampelAt(speed_raw_.data(), speed_raw_upto_, speed_upto_, hampel_half_, options_.hampel_nsigma, &out, scratch);
    speed_[speed_upto_++] = v * mpc;
  }
}

void StreamingFlow::ProcessProfiles() {
  std::vector<double> scratch;
  while (!profiles_.empty()) {
    const Pending& p = profiles_.front();
    const std::size_t j = static_cast<std::size_t>(p.index);
    const std::size_t have = area_window_.size();
    if (!finished_ && have <= j + static_cast<std::size_t>(options_.area_hampel_half)) return;
    // The log must have reached the profile's time with final positions.
    if (repaired_upto_ == 0 || (!finished_ && t_[repaired_upto_ - 1] < p.t_s)) return;
    // The walk runs backward from the profile's time, over repaired samples only.
    const ExtrusionTimeFinder finder(t_, counts_);
    const double p_k = UnwrapNear(p.raw, rig_.encoder, finder.PositionAt(p.t_s));
    const double target = p_k - rig_.offset_counts;
    const double t_e = finder.Find(p.t_s, target);
    // Its speed must be final around t_e.
    if (!finished_ && std::isfinite(t_e) && (speed_upto_ < 2 || t_[speed_upto_ - 1] < t_e)) return;
    bool out = false;
    double floor = options_.area_sigma_floor_mm2;
    if (floor < 0) {
      // The running median, refreshed each time the count doubles (amortised O(1)).
      if (area_sigmas_.size() >= 2 * floor_count_ && !area_sigmas_.empty()) {
        scratch = area_sigmas_;
        running_floor_ = MedianInPlace(scratch.data(), scratch.size());
        floor_count_ = area_sigmas_.size();
      }
      floor = running_floor_;
    }
    FlowSample s;
    s.profile = p.index;
    s.t_s = t_e;
    s.encoder = RawFromCounts(target, rig_.encoder);
    s.surface_speed_mm_s = InterpolateLinear(t_.data(), speed_.data(), speed_upto_, t_e);
    s.area_mm2 =
        HampelAt(area_window_.data(), have, j, options_.area_hampel_half, options_.hampel_nsigma, &out, scratch, floor);
    s.area_corrected_mm2 =
        HampelAt(area_c_window_.data(), have, j, options_.area_hampel_half, options_.hampel_nsigma, &out, scratch, floor);
    s.flow_mm3_s = s.surface_speed_mm_s * s.area_corrected_mm2;
    s.screw_rpm = InterpolateLinear(t_.data(), rpm_.data(), repaired_upto_, t_e);
    s.valid = std::isfinite(s.t_s) && std::isfinite(s.flow_mm3_s);
    ready_.push_back(s);
    profiles_.pop_front();
  }
}

bool StreamingFlow::Pop(FlowSample& out) {
  if (ready_.empty()) return false;
  out = ready_.front();
  ready_.pop_front();
  return true;
}

void StreamingFlow::Finish() {
  finished_ = true;
  if (!t_.empty()) repaired_upto_ = t_.size();
  ProcessLog();
  ProcessProfiles();
}

}  // namespace bead
