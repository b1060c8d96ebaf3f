// The exact median of a sequence too long to hold, in fixed memory: the
// sequence is walked again and again (a file read anew each time), and
// each walk narrows the value's bit pattern by 16 bits (a radix select
// over the order-preserving map of doubles to 64-bit keys); once the
// values sharing the bits found so far are few (at most kCollectAtMost),
// the next walk gathers them and the selection ends in memory. Usually two
// walks, at most four, for both middle values of every sequence at once.
// The result is MedianInPlace's (core/median.h) bit for bit: the middle
// value, or the mean of the two middle ones. NaN values are skipped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace bead {

// walk(visit) calls visit(value) for every value of the sequence, the same
// values each time it is called. Returns NaN for an empty sequence.
using Walk = std::function<void(const std::function<void(double)>&)>;
double MedianByWalks(const Walk& walk);

// Several sequences walked together: walk(visit) calls visit(s, value)
// for every value of sequence s (0 <= s < sequences). The medians, by
// sequence.
using Walks = std::function<void(const std::function<void(int, double)>&)>;
std::vector<double> MediansByWalks(int sequences, const Walks& walk);

// Values gathered in memory at most, per middle value sought (8 bytes each).
constexpr std::size_t kCollectAtMost = std::size_t{1} << 19;

}  // namespace bead
