#!/usr/bin/env bash
# mpirun -np 2 bead batch: the two ranks split the runs between them (each
# run measured by exactly one), and the summary ends with every run.
# Usage: mpirun_batch.sh BEAD_CLI
set -euo pipefail
bead="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for k in 1 2 3 4 5; do
  printf 'seed: %d\nduration_s: 2\nsensor: {points: 256}\npins: {scans: 1}\n' "$k" > "$work/c$k.yaml"
  "$bead" simulate "$work/c$k.yaml" -o "$work/run$k" > /dev/null
done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mpirun -np 2 "$bead" batch --threads 1 --rig "$work/run1/rig.yaml" -o "$work/out" "$work"/run*/run.h5 > "$work/log.txt" 2>&1 || {
  cat "$work/log.txt"; exit 1; }
cat "$work/log.txt"
fail=0
grep -q "shard 1/2: mpirun" "$work/log.txt" || { echo "FAIL: rank 0 did not take shard 1/2 from mpirun"; fail=1; }
grep -q "shard 2/2: mpirun" "$work/log.txt" || { echo "FAIL: rank 1 did not take shard 2/2 from mpirun"; fail=1; }
for k in 1 2 3 4 5; do
  n=$(grep -c "] run${k}_run: [0-9]* profiles" "$work/log.txt" || true)
  [ "$n" = 1 ] || { echo "FAIL: run$k measured $n times (once expected)"; fail=1; }
  [ -s "$work/out/run${k}_run/flow.csv" ] || { echo "FAIL: no flow.csv for run$k"; fail=1; }
done
rows=$(($(wc -l < "$work/out/summary.csv") - 1))
[ "$rows" = 5 ] || { echo "FAIL: summary.csv has $rows runs, 5 expected"; fail=1; }
[ $fail = 0 ] && echo "mpirun batch: 2 ranks, 5 runs, each once; summary complete"
exit $fail
