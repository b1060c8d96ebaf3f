#!/usr/bin/env bash
# Builds libbead and runs the whole test suite: once optimised, once under
# AddressSanitizer + UndefinedBehaviorSanitizer (set BEAD_SKIP_SANITIZE=1
# to skip that second pass while iterating).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

if [ "${BEAD_SKIP_SANITIZE:-0}" != "1" ]; then
  # Line tables only (-g1): enough for the sanitizers' stack traces, a fifth
  # less compile time on the Ceres-heavy sources than full debug info.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DBEAD_SANITIZE=ON -DBEAD_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan -j "$jobs"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j "$jobs"
fi
