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
constexpr std::size_t kAreas = 1024, kSigmas = 8192, kQueue = 4096;

// Drops the first `n` elements of v (no allocation: the capacity stays).
template <class T>
void DropFront(std::vector<T>& v, std::size_t n) {
  v.erase(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min(n, v.size())));
}

}  // namespace

StreamingFlow::StreamingFlow(const Rig& rig, const FlowOptions& options, double log_rate_hz, double history_s)
    : StreamingFlow(rig, options, WholeLogFacts{1.0 / log_rate_hz, EncoderOptions{}.min_glitch_counts}, history_s) {}

StreamingFlow::StreamingFlow(const Rig& rig, const FlowOptions& options, const WholeLogFacts& log, double history_s)
    : rig_(rig), options_(options), dt_(log.step_s), glitch_counts_(log.glitch_counts), unwrapper_(rig.encoder) {
  const double log_rate_hz = 1.0 / dt_;
  const int window = SpeedWindowSamples(options, dt_);
  sg_half_ = window / 2;
  sg_weights_ = SavgolWeights(window, std::min(options.speed_order, window - 1), 1, dt_, sg_half_);
  // The weights of the last window's fit (Finish), made here: Finish allocates nothing either.
  for (int p = 0; p < sg_half_; ++p) {
    const auto tail = SavgolWeights(window, std::min(options.speed_order, window - 1), 1, dt_, window - 1 - p);
    sg_tail_weights_.insert(sg_tail_weights_.end(), tail.begin(), tail.end());
  }
  hampel_half_ = std::max(1, static_cast<int>(std::lround(options.speed_hampel_s / dt_)));
  // The log: history_s and the filters' windows, twice over (compacted
  // by half when full).
  log_keep_ = static_cast<std::size_t>(std::ceil(std::max(history_s, 1.0) * log_rate_hz)) + sg_weights_.size() +
              static_cast<std::size_t>(2 * hampel_half_) + 4;
  for (auto* v : {&t_, &counts_, &rpm_, &speed_raw_, &speed_}) v->reserve(2 * log_keep_);
  raw_.reserve(2 * log_keep_);
  const std::size_t areas = std::max(kAreas, static_cast<std::size_t>(8 * options.area_hampel_half + 8));
  area_window_.reserve(2 * areas), area_c_window_.reserve(2 * areas);
  area_sigmas_.reserve(kSigmas);
  profiles_.reserve(2 * kQueue), ready_.reserve(2 * kQueue);
  scratch_.reserve(static_cast<std::size_t>(4 * std::max(hampel_half_, options.area_hampel_half) + 8));
  floor_scratch_.reserve(kSigmas);
}

// Drops the oldest half of the log once it holds twice what is kept, never
// a sample a filter window still reads.
void StreamingFlow::CompactLog() {
  if (t_.size() < 2 * log_keep_) return;
  const std::size_t in_use = std::min({repaired_upto_, speed_raw_upto_, speed_upto_});
  const std::size_t reach = sg_weights_.size() + static_cast<std::size_t>(2 * hampel_half_) + 2;
  const std::size_t drop = std::min(t_.size() - log_keep_, in_use > reach ? in_use - reach : 0);
  if (drop == 0) return;
  for (auto* v : {&t_, &counts_, &rpm_, &speed_raw_, &speed_}) DropFront(*v, drop);
  DropFront(raw_, drop);
  repaired_upto_ -= drop, speed_raw_upto_ -= drop, speed_upto_ -= drop, ranged_upto_ -= drop;
  log_dropped_ += drop;
}

// The same for the profiles' areas and the queues.
void StreamingFlow::CompactProfiles() {
  const std::size_t areas = area_window_.capacity() / 2;
  if (area_window_.size() >= 2 * areas) {
    const std::size_t oldest =
        profiles_head_ < profiles_.size() ? static_cast<std::size_t>(profiles_[profiles_head_].index) : next_profile_;
    const std::size_t half = static_cast<std::size_t>(options_.area_hampel_half) + 1;
    const std::size_t keep_from = oldest > half ? oldest - half : 0;
    const std::size_t drop = std::min(areas, keep_from > area_base_ ? keep_from - area_base_ : 0);
    DropFront(area_window_, drop), DropFront(area_c_window_, drop);
    area_base_ += drop;
  }
  if (profiles_head_ >= kQueue) DropFront(profiles_, profiles_head_), profiles_head_ = 0;
  if (ready_head_ >= kQueue) DropFront(ready_, ready_head_), ready_head_ = 0;
  if (area_sigmas_.size() >= kSigmas) DropFront(area_sigmas_, kSigmas / 2);
}

void StreamingFlow::PushLog(double t_s, int64_t raw, double screw_rpm) {
  CompactLog();
  t_.push_back(t_s);
  raw_.push_back(raw);
  counts_.push_back(unwrapper_.Push(raw));
  rpm_.push_back(screw_rpm);
  ProcessLog();
  ProcessProfiles();
}

void StreamingFlow::PushProfile(double t_s, int64_t raw, const BeadGeometry& g, double area_c, double area_c_sigma) {
  CompactProfiles();
  const double a = g.valid() ? g.area_mm2 : (g.status == ProfileStatus::kNoBead ? 0.0 : kNaN);
  profiles_.push_back({static_cast<int64_t>(next_profile_++), t_s, raw, a,
                       g.valid() && !std::isnan(area_c) ? area_c : a, area_c_sigma});
  area_window_.push_back(a);
  if (g.valid() && std::isfinite(g.area_sigma_mm2)) area_sigmas_.push_back(g.area_sigma_mm2), ++sigmas_seen_;
  area_c_window_.push_back(profiles_.back().area_c);
  ProcessProfiles();
}

void StreamingFlow::ProcessLog() {
  const std::size_t n = t_.size();
  // Missed reads and glitches, one sample late (the batch's rule at the fixed threshold).
  while (repaired_upto_ + 1 < n) {
    const std::size_t i = repaired_upto_;
    double value = 0.0;
    if (i >= 1 &&
        RepairEncoderSample(counts_.data(), raw_.data(), t_.data(), i, glitch_counts_, &value) != EncoderRepair::kNone)
      counts_[i] = value, ++encoder_repairs_;
    ++repaired_upto_;
  }
  for (; ranged_upto_ < repaired_upto_; ++ranged_upto_)
    counts_min_ = std::min(counts_min_, counts_[ranged_upto_]),
    counts_max_ = std::max(counts_max_, counts_[ranged_upto_]);
  // Speed by the Savitzky-Golay derivative once its window is final.
  speed_raw_.resize(n, kNaN);
  const std::size_t w = sg_weights_.size();
  while (speed_raw_upto_ + sg_half_ < repaired_upto_ && speed_raw_upto_ >= static_cast<std::size_t>(sg_half_)) {
    double acc = 0.0;
    for (std::size_t j = 0; j < w; ++j) acc += sg_weights_[j] * counts_[speed_raw_upto_ - sg_half_ + j];
    speed_raw_[speed_raw_upto_++] = acc;
  }
  if (finished_ && n >= w && speed_raw_upto_ + sg_half_ == n) {
    // The run's last samples: the polynomial fitted to the last window, as
    // the batch's interp mode (SavgolFilter).
    for (std::size_t p = static_cast<std::size_t>(sg_half_); p-- > 0;) {
      const double* tail = sg_tail_weights_.data() + p * w;
      double acc = 0.0;
      for (std::size_t j = 0; j < w; ++j) acc += tail[j] * counts_[n - w + j];
      speed_raw_[n - 1 - p] = acc;
    }
    speed_raw_upto_ = n;
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
  std::vector<double>& scratch = scratch_;
  const double mpc = rig_.MmPerCount();
  while (speed_upto_ + hampel_half_ < speed_raw_upto_ || (finished_ && speed_upto_ < speed_raw_upto_)) {
    bool out = false;
    const double v =
        HampelAt(speed_raw_.data(), speed_raw_upto_, speed_upto_, hampel_half_, options_.hampel_nsigma, &out, scratch);
    speed_outliers_ += out;
    speed_[speed_upto_++] = v * mpc;
  }
}

void StreamingFlow::ProcessProfiles() {
  std::vector<double>& scratch = scratch_;
  while (profiles_head_ < profiles_.size()) {
    const Pending& p = profiles_[profiles_head_];
    const std::size_t j = static_cast<std::size_t>(p.index) - area_base_;  // in the kept window
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
      // The running median of the sigmas kept (the last 8192 at most),
      // refreshed each time the count seen doubles, and every 4096 beyond
      // (amortised O(1)).
      if (!area_sigmas_.empty() && (sigmas_seen_ >= 2 * floor_count_ || sigmas_seen_ >= floor_count_ + kSigmas / 2)) {
        floor_scratch_.assign(area_sigmas_.begin(), area_sigmas_.end());
        running_floor_ = MedianInPlace(floor_scratch_.data(), floor_scratch_.size());
        floor_count_ = sigmas_seen_;
      }
      floor = running_floor_;
    }
    FlowSample s;
    s.profile = p.index;
    s.t_s = t_e;
    s.encoder = RawFromCounts(target, rig_.encoder);
    // An eccentric wheel carried this material at its own radius (as the batch).
    s.surface_speed_mm_s = InterpolateLinear(t_.data(), speed_.data(), speed_upto_, t_e) * rig_.SurfaceSpeedFactor(p_k);
    s.area_mm2 =
        HampelAt(area_window_.data(), have, j, options_.area_hampel_half, options_.hampel_nsigma, &out, scratch, floor);
    area_outliers_ += out;
    if (std::isnan(t_e) && log_dropped_ > 0) ++history_misses_;
    s.area_corrected_mm2 = HampelAt(area_c_window_.data(), have, j, options_.area_hampel_half, options_.hampel_nsigma,
                                    &out, scratch, floor);
    s.flow_mm3_s = s.surface_speed_mm_s * s.area_corrected_mm2;
    s.occlusion_bias_mm2 = s.area_mm2 - s.area_corrected_mm2;
    s.area_corrected_sigma_mm2 = p.area_c_sigma;
    s.flow_sigma_mm3_s = s.surface_speed_mm_s * p.area_c_sigma;
    s.screw_rpm = InterpolateLinear(t_.data(), rpm_.data(), repaired_upto_, t_e);
    s.valid = std::isfinite(s.t_s) && std::isfinite(s.flow_mm3_s);
    ready_.push_back(s);
    ++profiles_head_;
  }
  if (profiles_head_ == profiles_.size()) profiles_.clear(), profiles_head_ = 0;
}

bool StreamingFlow::Pop(FlowSample& out) {
  if (ready_head_ >= ready_.size()) return false;
  out = ready_[ready_head_++];
  if (ready_head_ == ready_.size()) ready_.clear(), ready_head_ = 0;
  return true;
}

void StreamingFlow::Finish() {
  finished_ = true;
  if (!t_.empty()) repaired_upto_ = t_.size();
  ProcessLog();
  ProcessProfiles();
}

}  // namespace bead
