// BEAD_HOT: marks the per-profile entry points for one build per
// instruction set, chosen when the program loads (GCC target_clones, an
// ELF ifunc): AVX2 where the processor has it, the x86-64 baseline (SSE2)
// otherwise. The vectorised loops then run 8 floats wide instead of 4.
// `flatten` inlines the helpers they call into each build, so the
// helpers' loops get the wider vectors too.
// Sums reordered for vectors round differently in the last bits of a
// float on the two builds; nothing else differs.
#pragma once

#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define BEAD_HOT __attribute__((target_clones("avx2", "default"), flatten))
#else
#define BEAD_HOT
#endif
