#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan) and runs
# each for SECONDS (default 20) on its seed corpus (fuzz/corpus/<target>),
# new inputs kept in build-fuzz/work/<target>. One line per target:
#   <target>: <executions> executions, <crashes> crashes
# and exit status 1 when any target crashed in libbead's code (the inputs
# in build-fuzz/crashes/<target>/, each with its .report, the fuzzer's log
# beside them). A crash, hang or runaway allocation whose stack reaches
# libhdf5 or libmatio before any code of ours (Debian 12's HDF5 1.10.8 and
# matio 1.5.23 on a corrupt file) is upstream's: reported on a line of its
# own, not counted. A kept input that runs clean three times alone is
# counted only where the fuzzer saw the caller itself crash; otherwise it
# is a contained probe's (a forked child reading a corrupt file writes an
# artifact as the fuzzer would, while the caller refuses the file as
# designed) or a loaded machine's timeout, listed on a line of its own.
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
for t in "${targets[@]}"; do
  [ -d "fuzz/corpus/$t" ] || { echo "fuzz.sh: no target '$t' (targets: $(ls fuzz/corpus | tr '\n' ' '))" >&2; exit 2; }
done
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DBEAD_FUZZ=ON >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]/%/_fuzz}"

# Whose code a report's stack is in: the first frame that is either in
# libhdf5 or libmatio, or in a source file of ours (libbead/, calibration/, tools/, a
# fuzz target) decides. Every other frame is the sanitizer's or libFuzzer's
# runtime, an interceptor (strdup, memset: they carry no file of ours), libc
# or libstdc++, and says nothing about whose bug it is. "libhdf5": a crash,
# hang or runaway allocation inside HDF5 itself on a corrupt file: upstream's
# bug, kept and reported, not counted as libbead's.
classify() {
  local frame
  frame=$(grep -E '^ +#[0-9]+ ' "$1" | grep -E 'libhdf5|libmatio|/libbead/|/calibration/|/tools/[a-z_]+\.cc|/fuzz/[a-z_]+\.cc' | head -1)
  case "$frame" in *libhdf5* | *libmatio*) echo upstream ;; *) echo ours ;; esac
}

# One target: its fuzzing, then each kept input re-run alone and classified;
# its lines in $crashes/summary, and exit 1 when it crashed in our code.
fuzz_target() {
  local t=$1 work=build-fuzz/work/$1 crashes=build-fuzz/crashes/$1
  mkdir -p "$work" "$crashes"
  rm -f "$crashes"/crash-* "$crashes"/leak-* "$crashes"/timeout-* "$crashes"/oom-* "$crashes"/*.report
  log=$crashes/fuzz.log
  env=(ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
       UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1)
  # Fork mode goes on after a crash (each input's artifact kept), so a bug
  # found early does not end the search. -rss_limit_mb: a reader asked for
  # an absurd size must refuse it, not try to allocate it.
  env "${env[@]}" "build-fuzz/fuzz/${t}_fuzz" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -artifact_prefix="$crashes/" "$work" \
    "fuzz/corpus/$t" >"$log" 2>&1 || true
  runs=$(grep -o -E '^#[0-9]+:' "$log" | tail -1 | tr -d '#:')
  # The fuzzer's own count of its jobs that crashed: the caller's crashes.
  # A contained probe (libbead/io/contained: a forked child reading a
  # corrupt file's metadata) is a copy of the fuzzer, so its crash also
  # writes an artifact, yet the caller only sees a probe that failed and
  # refuses the file, as designed: such artifacts are not in this count.
  caller=$(grep -o -E 'oom/timeout/crash: [0-9]+/[0-9]+/[0-9]+' "$log" | tail -1 | grep -o -E '[0-9]+$' || true)
  caller=${caller:-0}
  ours=0 upstream=0 alone=0 probe=0 said=""
  for a in "$crashes"/crash-* "$crashes"/leak-* "$crashes"/timeout-* "$crashes"/oom-*; do
    [ -e "$a" ] || continue
    case "$a" in *.report) continue ;; esac
    # An out-of-memory input is re-run with allocations over 2 GB refused
    # outright, so that the report holds the stack of the one who asked.
    rerun=("${env[@]}")
    case "$a" in */oom-*) rerun[0]=ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=0:max_allocation_size_mb=2048 ;; esac
    # Up to three times: a corrupt file can make libhdf5 read memory it
    # never wrote, whose contents (and so the crash) depend on the inputs
    # run before it.
    for try in 1 2 3; do
      env "${rerun[@]}" "build-fuzz/fuzz/${t}_fuzz" -runs=1 -timeout=20 -rss_limit_mb=2048 "$a" >"$a.report" 2>&1 || true
      grep -q -E 'ERROR|SUMMARY|runtime error|terminate' "$a.report" && break
    done
    if grep -q -E 'ERROR|SUMMARY|runtime error|terminate' "$a.report"; then
      if [ "$(classify "$a.report")" = upstream ]; then
        upstream=$((upstream + 1))
      else
        ours=$((ours + 1))
        said+="$(grep -m 2 -E 'ERROR|SUMMARY|runtime error|terminate' "$a.report" | sed 's/^/  /')"$'\n'
      fi
    elif [ "${a#*/oom-}" != "$a" ] || [ "${a#*/timeout-}" != "$a" ]; then
      # Fork mode calls out of memory when a child's resident size, grown
      # over many inputs, passes the limit; the input it ran last is kept.
      # A timeout: an input slow only on a machine loaded by the other
      # lanes (a probe's time limits stretch while it is starved:
      # io/contained.h). Run alone and clean, it asked for nothing absurd
      # and hung nowhere: listed apart, not counted either way.
      alone=$((alone + 1))
    elif [ "$caller" -eq 0 ]; then
      # Clean alone, and the caller never failed: a contained probe's crash
      # that did not come back. Listed apart; when the caller itself failed,
      # an input that does not come back is counted as ours.
      probe=$((probe + 1))
    else
      ours=$((ours + 1))
      said+="  $a: clean in three runs alone, while the fuzzer counted $caller crash(es) of its own"$'\n'
    fi
  done
  {
    echo "$t: ${runs:-0} executions, $ours crashes"
    [ "$upstream" -eq 0 ] || echo "  ($upstream more inside libhdf5 or libmatio itself on a corrupt file: upstream; reports in $crashes/*.report)"
    [ "$alone" -eq 0 ] || echo "  ($alone out-of-memory or timed-out input(s) run clean alone: memory grown over a fork's many inputs, or a loaded machine; in $crashes)"
    [ "$probe" -eq 0 ] || echo "  ($probe input(s) whose contained probe crashed while fuzzing, clean in three runs alone; the caller never failed; in $crashes)"
    printf '%s' "$said"
  } >"$crashes/summary"
  [ "$ours" -eq 0 ]
}

# The targets in as many lanes as there are processors (each fuzzer runs
# one process at a time), then their lines in the targets' order.
lanes=$(nproc)
for ((lane = 0; lane < lanes; lane++)); do
  (
    lane_failed=0
    for ((i = lane; i < ${#targets[@]}; i += lanes)); do
      fuzz_target "${targets[i]}" || lane_failed=1
    done
    exit "$lane_failed"
  ) &
done
failed=0
for ((lane = 0; lane < lanes; lane++)); do
  wait -n || failed=1
done
for t in "${targets[@]}"; do
  cat "build-fuzz/crashes/$t/summary"
done
exit "$failed"
