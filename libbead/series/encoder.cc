#include "libbead/series/encoder.h"

#include "libbead/core/median.h"

#include <algorithm>
#include <cmath>

namespace bead {
namespace {

// Signed step between two raw reads, modulo the counter width.
int64_t Step(int64_t from, int64_t to, int bits) {
  int64_t d = to - from;
  if (bits > 0 && bits < 64) {
    const int64_t modulus = int64_t{1} << bits;
    d %= modulus;
    if (d >= modulus / 2) d -= modulus;
    if (d < -modulus / 2) d += modulus;
  }
  return d;
}

}  // namespace

EncoderRepair RepairEncoderSample(const double* c, const int64_t* raw, const double* t, std::size_t i,
                                  double glitch_counts, double* repaired) {
  const double before = c[i] - c[i - 1], after = c[i + 1] - c[i];
  const double f = (t[i] - t[i - 1]) / (t[i + 1] - t[i - 1]);
  *repaired = c[i - 1] + f * (c[i + 1] - c[i - 1]);
  // A repeated read between two reads that move the same way.
  const double prev_step = i >= 2 ? c[i - 1] - c[i - 2] : after;
  if (raw[i] == raw[i - 1] && after != 0.0 && prev_step != 0.0 && (prev_step > 0) == (after > 0))
    return EncoderRepair::kMissedRead;
  // A glitch: a step out (+g) and straight back (-g).
  if (std::abs(c[i] - *repaired) > glitch_counts && std::abs(before + after) < 0.5 * std::abs(before))
    return EncoderRepair::kGlitch;
  return EncoderRepair::kNone;
}

EncoderTrack UnwrapEncoder(const std::vector<int64_t>& raw, const EncoderSpec& spec, const std::vector<double>& t_s,
                           const EncoderOptions& options) {
  EncoderTrack track;
  const std::size_t n = raw.size();
  track.counts.resize(n);
  track.repaired.assign(n, 0);
  if (n == 0) return track;
  double pos = spec.direction * static_cast<double>(raw[0]);
  track.counts[0] = pos;
  for (std::size_t i = 1; i < n; ++i) {
    pos += spec.direction * static_cast<double>(Step(raw[i - 1], raw[i], spec.bits));
    track.counts[i] = pos;
  }
  auto time = [&](std::size_t i) { return t_s.size() == n ? t_s[i] : static_cast<double>(i); };
  auto predicted = [&](std::size_t i) {
    const double f = (time(i) - time(i - 1)) / (time(i + 1) - time(i - 1));
    return track.counts[i - 1] + f * (track.counts[i + 1] - track.counts[i - 1]);
  };
  if (n < 3) return track;
  // Glitch threshold from the second differences' robust spread.
  std::vector<double> second;
  for (std::size_t i = 1; i + 1 < n; ++i) second.push_back(std::abs(track.counts[i] - predicted(i)));
  const double sigma = second.empty() ? 0.0 : 1.4826 * MedianInPlace(second.data(), second.size());
  const double glitch = std::max(options.min_glitch_counts, 8.0 * sigma);
  std::vector<double> even;
  if (t_s.size() != n) {
    even.resize(n);
    for (std::size_t i = 0; i < n; ++i) even[i] = static_cast<double>(i);
  }
  const double* t = t_s.size() == n ? t_s.data() : even.data();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    double value = 0.0;
    const EncoderRepair kind = RepairEncoderSample(track.counts.data(), raw.data(), t, i, glitch, &value);
    if (kind == EncoderRepair::kNone) continue;
    track.counts[i] = value;
    track.repaired[i] = 1;
    ++(kind == EncoderRepair::kMissedRead ? track.missed_reads : track.glitches);
  }
  return track;
}

double CountsToAngleRad(double counts, const EncoderSpec& spec) { return 2.0 * M_PI * counts / spec.counts_per_rev; }

double CountsToMm(double counts, const Rig& rig) { return counts * rig.MmPerCount(); }

double UnwrapNear(int64_t raw, const EncoderSpec& spec, double near_counts) {
  const double base = spec.direction * static_cast<double>(raw);
  if (spec.bits <= 0 || spec.bits >= 64) return base;
  const double modulus = std::ldexp(1.0, spec.bits);
  return base + modulus * std::round((near_counts - base) / modulus);
}

int64_t RawFromCounts(double counts, const EncoderSpec& spec) {
  int64_t raw = static_cast<int64_t>(std::llround(counts * spec.direction));
  if (spec.bits > 0 && spec.bits < 64) {
    const int64_t modulus = int64_t{1} << spec.bits;
    raw %= modulus;
    if (raw < 0) raw += modulus;
  }
  return raw;
}

double EncoderUnwrapper::Push(int64_t raw) {
  if (!started_) {
    started_ = true;
    position_ = spec_.direction * static_cast<double>(raw);
  } else {
    position_ += spec_.direction * static_cast<double>(Step(last_raw_, raw, spec_.bits));
  }
  last_raw_ = raw;
  return position_;
}

}  // namespace bead
