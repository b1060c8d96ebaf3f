#include "libbead/flow/extrusion_time.h"

#include <algorithm>
#include <cmath>

namespace bead {

ExtrusionTimeFinder::ExtrusionTimeFinder(const std::vector<double>& log_t_s, const std::vector<double>& log_counts)
    : t_(log_t_s), p_(log_counts) {}

namespace {

// The least and greatest of p over samples [b size, (b + 1) size] of each full run of `size` segments.
void RangesOf(const std::vector<double>& p, std::size_t size, std::vector<double>& lo, std::vector<double>& hi) {
  const std::size_t runs = p.empty() ? 0 : (p.size() - 1) / size;
  lo.resize(runs);
  hi.resize(runs);
  for (std::size_t b = 0; b < runs; ++b) {
    const auto [l, h] = std::minmax_element(p.begin() + static_cast<std::ptrdiff_t>(b * size),
                                            p.begin() + static_cast<std::ptrdiff_t>((b + 1) * size + 1));
    lo[b] = *l, hi[b] = *h;
  }
}

}  // namespace

void ExtrusionTimeFinder::BuildIndex() {
  RangesOf(p_, kBlock, block_min_, block_max_);
  RangesOf(p_, kSpan, span_min_, span_max_);
}

double ExtrusionTimeFinder::PositionAt(double t) const {
  if (t_.empty()) return std::nan("");
  if (t <= t_.front()) return p_.front();
  if (t >= t_.back()) return p_.back();
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const std::size_t j = static_cast<std::size_t>(it - t_.begin());
  const double f = (t - t_[j - 1]) / (t_[j] - t_[j - 1]);
  return p_[j - 1] + f * (p_[j] - p_[j - 1]);
}

ExtrusionTimeFinder::Start ExtrusionTimeFinder::StartAt(double t_measured) const {
  Start s;
  if (t_.empty()) return s;
  s.j = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t_measured) - t_.begin());
  if (s.j == 0) return s;
  s.t_s = std::min(t_measured, t_.back());
  s.counts = PositionAt(s.t_s);
  return s;
}

double ExtrusionTimeFinder::Find(const Start& from, double target) const {
  const std::size_t n = t_.size();
  // Start from the segment holding t_measured, with the position there.
  const std::size_t j = from.j;
  if (n == 0 || j == 0) return std::nan("");
  double hi_t = from.t_s;
  double hi_p = from.counts;
  if (hi_p == target) return hi_t;
  // Walk back segment by segment: [t_[k], hi_t] with positions [p_[k], hi_p].
  for (std::size_t k = std::min(j, n) - 1, first = 1;; --k, first = 0) {
    // Past the first segment its upper end is the sample k + 1. When that
    // ends a block whose positions all miss the target, none of the
    // block's segments holds a crossing: on to the sample that starts it.
    while (!first && !block_min_.empty() && (k + 1) % kBlock == 0) {
      if ((k + 1) % kSpan == 0) {  // it ends a span too: the span's range first
        const std::size_t sp = (k + 1) / kSpan - 1;
        if (!(target >= span_min_[sp] && target <= span_max_[sp])) {
          if (sp == 0) return std::nan("");
          k -= kSpan;
          hi_t = t_[k + 1];
          hi_p = p_[k + 1];
          continue;
        }
      }
      const std::size_t b = (k + 1) / kBlock - 1;
      if (target >= block_min_[b] && target <= block_max_[b]) break;
      if (b == 0) return std::nan("");
      k -= kBlock;
      hi_t = t_[k + 1];
      hi_p = p_[k + 1];
    }
    const double lo_t = t_[k], lo_p = p_[k];
    if ((lo_p - target) * (hi_p - target) <= 0.0 && lo_p != hi_p) {
      // The latest crossing in this segment is found from its upper end.
      const double f = (hi_p - target) / (hi_p - lo_p);
      return hi_t - f * (hi_t - lo_t);
    }
    if (lo_p == target) {
      // Standing at the target: the wheel left it at the end of the stop.
      return lo_t;
    }
    if (k == 0) break;
    hi_t = lo_t;
    hi_p = lo_p;
  }
  return std::nan("");
}

}  // namespace bead
