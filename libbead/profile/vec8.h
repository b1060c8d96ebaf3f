// Eight floats at a time, written with GCC's vector extensions so that one
// source builds to AVX2 (one register) or SSE2 (two) - see kernel.h; the
// mask reductions use AVX's own instructions where they are built for it.
// Only what the per-profile loops need.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

// The helpers are always inlined, so no vector crosses a call (GCC's
// -Wpsabi note about the AVX calling convention does not apply; the
// sources using them build with -Wno-psabi).
#define BEAD_VEC inline __attribute__((always_inline))

namespace bead::vec {

typedef float V8 __attribute__((vector_size(32)));
typedef int32_t M8 __attribute__((vector_size(32)));  // lanes all ones (true) or zero

BEAD_VEC V8 Load(const float* p) {
  V8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
BEAD_VEC void Store(float* p, V8 v) { std::memcpy(p, &v, sizeof v); }
BEAD_VEC V8 Splat(float x) { return V8{} + x; }
BEAD_VEC V8 Abs(V8 v) { return v < 0.0f ? -v : v; }
BEAD_VEC V8 Select(M8 m, V8 a, V8 b) { return m ? a : b; }  // a where m, else b
BEAD_VEC V8 Min(V8 a, V8 b) { return a < b ? a : b; }
BEAD_VEC V8 Max(V8 a, V8 b) { return a > b ? a : b; }
// Lane-wise median of three (the same formula as median.h's Median3).
BEAD_VEC V8 Median3(V8 a, V8 b, V8 c) { return Max(Min(a, b), Min(Max(a, b), c)); }
BEAD_VEC V8 ToFloat(M8 m) { return Select(m, Splat(1.0f), Splat(0.0f)); }
// The lanes of the eight points from `start` that are at or after `from`
// (from >= start): a range's last, partial eight is loaded as the whole
// eight ending at its end, the lanes already taken masked off.
BEAD_VEC M8 LanesFrom(std::size_t start, std::size_t from) {
  return M8{0, 1, 2, 3, 4, 5, 6, 7} >= static_cast<int32_t>(from - start);
}

// Horizontal reductions: by halving; the mask tests and the lanes' truth
// as bits (lane i: bit i) with AVX's own instructions where built for it.
BEAD_VEC float Sum(V8 v) {
  const V8 a = v + __builtin_shufflevector(v, v, 4, 5, 6, 7, 0, 1, 2, 3);
  const V8 b = a + __builtin_shufflevector(a, a, 2, 3, 0, 1, 2, 3, 0, 1);
  return b[0] + b[1];
}
BEAD_VEC int32_t SumInt(M8 v) {
  const M8 a = v + __builtin_shufflevector(v, v, 4, 5, 6, 7, 0, 1, 2, 3);
  const M8 b = a + __builtin_shufflevector(a, a, 2, 3, 0, 1, 2, 3, 0, 1);
  return b[0] + b[1];
}
#ifdef __AVX2__
typedef long long V4L __attribute__((vector_size(32)));
BEAD_VEC bool Any(M8 m) { return !__builtin_ia32_ptestz256((V4L)m, (V4L)m); }
BEAD_VEC bool All(M8 m) { return __builtin_ia32_movmskps256((V8)m) == 0xff; }
BEAD_VEC int Bits(M8 m) { return __builtin_ia32_movmskps256((V8)m); }
#else
BEAD_VEC bool Any(M8 m) {
  const auto a =
      __builtin_shufflevector(m, m, 0, 1, 2, 3, 0, 1, 2, 3) | __builtin_shufflevector(m, m, 4, 5, 6, 7, 4, 5, 6, 7);
  const auto b = a | __builtin_shufflevector(a, a, 2, 3, 0, 1, 2, 3, 0, 1);
  return (b[0] | b[1]) != 0;
}
BEAD_VEC bool All(M8 m) { return !Any(~m); }
BEAD_VEC int Bits(M8 m) { return SumInt(m & M8{1, 2, 4, 8, 16, 32, 64, 128}); }
#endif
BEAD_VEC float MaxOf(V8 v) {
  const V8 a = Max(v, __builtin_shufflevector(v, v, 4, 5, 6, 7, 0, 1, 2, 3));
  const V8 b = Max(a, __builtin_shufflevector(a, a, 2, 3, 0, 1, 2, 3, 0, 1));
  return b[0] > b[1] ? b[0] : b[1];
}

// Left-packing: for each 8-bit lane set, the indices of its lanes in order,
// then the others (a vector permutation; AVX2 does it in one instruction).
struct PackTable {
  int32_t index[256][8];
};
constexpr PackTable MakePackTable() {
  PackTable t{};
  for (int bits = 0; bits < 256; ++bits) {
    int k = 0;
    for (int lane = 0; lane < 8; ++lane)
      if (bits & (1 << lane)) t.index[bits][k++] = lane;
    for (int lane = 0; lane < 8; ++lane)
      if (!(bits & (1 << lane))) t.index[bits][k++] = lane;
  }
  return t;
}
inline constexpr PackTable kPackTable = MakePackTable();
BEAD_VEC M8 PackIndex(int bits) {
  M8 m;
  std::memcpy(&m, kPackTable.index[bits], sizeof m);
  return m;
}
// The lanes of v set in `bits` first, in order (the rest after them), with
// index = PackIndex(bits).
#if defined(__clang__)
// clang has no shuffle by a run-time index vector: lane by lane (it builds
// the fuzz targets, not the shipped kernel).
BEAD_VEC V8 Pack(V8 v, M8 index) {
  V8 r;
  for (int lane = 0; lane < 8; ++lane) r[lane] = v[index[lane] & 7];
  return r;
}
#else
BEAD_VEC V8 Pack(V8 v, M8 index) { return __builtin_shuffle(v, index); }
#endif

}  // namespace bead::vec

#undef BEAD_VEC
