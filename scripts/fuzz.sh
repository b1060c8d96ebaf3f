#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan) and runs
# each for SECONDS (default 20) on its seed corpus (fuzz/corpus/<target>),
# new inputs kept in build-fuzz/work/<target>. One line per target:
#   <target>: <executions> executions, <crashes> crashes
# and exit status 1 when any target crashed (the input is in
# build-fuzz/crashes/<target>/, the fuzzer's log beside it).
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
case "$seconds" in '' | *[!0-9]*) echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2 ;; esac
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  mapfile -t targets < <(ls fuzz/corpus)
fi
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DBEAD_FUZZ=ON >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]/%/_fuzz}"

failed=0
for t in "${targets[@]}"; do
  work=build-fuzz/work/$t crashes=build-fuzz/crashes/$t
  mkdir -p "$work" "$crashes"
  rm -f "$crashes"/crash-* "$crashes"/leak-* "$crashes"/timeout-* "$crashes"/oom-*
  log=$crashes/fuzz.log
  # -rss_limit_mb: a reader asked for an absurd size must refuse it, not
  # try to allocate it; 2 GB is far beyond any seed's need.
  status=0
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "build-fuzz/fuzz/${t}_fuzz" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$work" "fuzz/corpus/$t" >"$log" 2>&1 || status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  found=$(find "$crashes" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  if [ "$status" -ne 0 ] && [ "$found" -eq 0 ]; then found=1; fi  # died without an artifact
  echo "$t: ${runs:-0} executions, $found crashes"
  if [ "$found" -ne 0 ]; then
    failed=1
    grep -m 3 -E 'ERROR|SUMMARY|terminate' "$log" | sed 's/^/  /' || true
  fi
done
exit "$failed"
