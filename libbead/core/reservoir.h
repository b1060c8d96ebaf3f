// A bounded sample of a stream of values, for its quantiles in memory that
// does not grow with the stream (a scan's summary over millions of rows):
// the first kSize values kept, then the n-th kept with probability kSize / n
// in place of one chosen at random (reservoir sampling: Vitter 1985, ACM
// TOMS 11, algorithm R), from a fixed seed, so the same stream gives the same
// sample. A quantile of kSize values is within about 1 / sqrt(kSize), 0.4 %,
// of the stream's in rank.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bead {

class Reservoir {
 public:
  static constexpr std::size_t kSize = std::size_t{1} << 16;

  void Add(double value) {
    ++seen_;
    if (kept_.size() < kSize) return kept_.push_back(value);
    const uint64_t slot = Next() % seen_;
    if (slot < kSize) kept_[slot] = value;
  }
  std::size_t seen() const { return seen_; }  // the values added
  bool empty() const { return seen_ == 0; }
  // The value q of the way up the kept ones (the element at q n, the upper
  // of two middles for q = 0.5); NaN where none.
  double Quantile(double q) const {
    if (kept_.empty()) return NAN;
    std::vector<double> v = kept_;
    const auto at = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(at), v.end());
    return v[at];
  }

 private:
  // splitmix64 (Steele, Lea and Flood 2014): a fixed sequence from the seed.
  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::vector<double> kept_;
  std::size_t seen_ = 0;
  uint64_t state_ = 0;
};

}  // namespace bead
