// Whether a float or a double is NaN, or finite, told by its bits. A
// floating comparison may trap, so the x86-64 build keeps a branch for each
// such test and does not vectorise the loop around it; the kernels'
// associative math folds v - v to 0. An integer test does neither.
#pragma once

#include <bit>
#include <cstdint>

namespace bead {

inline bool IsNanBits(float v) { return (std::bit_cast<uint32_t>(v) & 0x7fffffffu) > 0x7f800000u; }
inline bool IsFiniteBits(float v) { return (std::bit_cast<uint32_t>(v) & 0x7f800000u) != 0x7f800000u; }
inline bool IsFiniteBits(double v) {
  constexpr uint64_t kExponent = 0x7ff0000000000000u;
  return (std::bit_cast<uint64_t>(v) & kExponent) != kExponent;
}

}  // namespace bead
