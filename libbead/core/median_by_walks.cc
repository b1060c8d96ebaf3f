#include "libbead/core/median_by_walks.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "libbead/core/error.h"

namespace bead {
namespace {

// Doubles to keys in the same order (negatives reversed below positives).
uint64_t Key(double v) {
  uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  return (u >> 63) ? ~u : u | (uint64_t{1} << 63);
}

double FromKey(uint64_t k) {
  const uint64_t u = (k >> 63) ? k & ~(uint64_t{1} << 63) : ~k;
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

// The search for the k-th smallest key (0-based) of one sequence.
struct Selection {
  uint64_t k = 0;
  uint64_t prefix = 0;  // the key's high `known` bits found so far
  int known = 0;
  uint64_t matching = 0;  // values whose key starts with prefix
  bool collect = false;   // the next walk gathers them
  bool done = false;
  uint64_t key = 0;  // the answer, once done
  std::vector<uint64_t> counts, gathered;

  bool Matches(uint64_t key_of) const { return known == 0 || (key_of >> (64 - known)) == prefix; }
  void Visit(uint64_t key_of) {
    if (done || !Matches(key_of)) return;
    if (collect)
      gathered.push_back(key_of);
    else
      ++counts[(key_of >> (64 - known - 16)) & 0xffff];
  }
  void Prepare() {
    if (done) return;
    collect = known > 0 && matching <= kCollectAtMost;
    if (collect) {
      gathered.clear();
      gathered.reserve(matching);
    } else {
      counts.assign(1u << 16, 0);
    }
  }
  void Settle() {
    if (done) return;
    if (collect) {
      if (gathered.size() != matching) throw Error("MediansByWalks: the walked sequence changed between walks");
      std::nth_element(gathered.begin(), gathered.begin() + static_cast<std::ptrdiff_t>(k), gathered.end());
      key = gathered[k], done = true;
      gathered = {};
      return;
    }
    uint64_t digit = 0;
    for (; digit < 0xffff && k >= counts[digit]; ++digit) k -= counts[digit];
    matching = counts[digit];
    prefix = (prefix << 16) | digit, known += 16;
    if (known == 64) key = prefix, done = true;
  }
};

}  // namespace

std::vector<double> MediansByWalks(int sequences, const Walks& walk) {
  const std::size_t m = static_cast<std::size_t>(std::max(sequences, 0));
  // The first walk counts every sequence and narrows by the top 16 bits for
  // both middle values; their ranks come from the counts.
  std::vector<std::vector<uint64_t>> top(m, std::vector<uint64_t>(1u << 16, 0));
  walk([&](int s, double v) {
    if (!std::isnan(v)) ++top[static_cast<std::size_t>(s)][Key(v) >> 48];
  });
  std::vector<Selection> sel(2 * m);  // upper and lower middle of each sequence
  std::vector<uint64_t> n(m, 0);
  for (std::size_t s = 0; s < m; ++s) {
    for (uint64_t c : top[s]) n[s] += c;
    for (int lower = 0; lower < 2; ++lower) {
      Selection& x = sel[2 * s + static_cast<std::size_t>(lower)];
      if (n[s] == 0 || (lower && n[s] % 2 == 1)) {
        x.done = true;
        continue;
      }
      x.k = n[s] / 2 - static_cast<uint64_t>(lower);
      x.counts = top[s];
      x.Settle();
    }
  }
  top.clear();
  while (std::any_of(sel.begin(), sel.end(), [](const Selection& x) { return !x.done; })) {
    for (Selection& x : sel) x.Prepare();
    walk([&](int s, double v) {
      if (std::isnan(v)) return;
      const uint64_t key = Key(v);
      sel[2 * static_cast<std::size_t>(s)].Visit(key);
      sel[2 * static_cast<std::size_t>(s) + 1].Visit(key);
    });
    for (Selection& x : sel) x.Settle();
  }
  std::vector<double> medians(m, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t s = 0; s < m; ++s) {
    if (n[s] == 0) continue;
    const double upper = FromKey(sel[2 * s].key);
    medians[s] = n[s] % 2 == 1 ? upper : 0.5 * (upper + FromKey(sel[2 * s + 1].key));
  }
  return medians;
}

double MedianByWalks(const Walk& walk) {
  return MediansByWalks(
      1, [&](const std::function<void(int, double)>& visit) { walk([&](double v) { visit(0, v); }); })[0];
}

}  // namespace bead
