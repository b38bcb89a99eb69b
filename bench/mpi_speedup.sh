#!/usr/bin/env bash
# Speed-up of `podid landscape` on MPI ranks, measured side by side in one run:
# one process with one thread, then 2 ranks with one thread each, on the same
# grid (the reference beam, 1 s record, knl 0..200, full + time-free).
# Usage: bash bench/mpi_speedup.sh [PODID] [POINTS]   (from the repo root)
# Needs two otherwise idle cores for the 1.8x of issue 14.
set -euo pipefail
podid="${1:-build/release/apps/podid}"
points="${2:-201}"
args=(landscape examples/beam.toml --measured examples/measured_knl50_T1.0.csv --param knl
      --range "0:200:$points" --objective full,time-free --threads 1)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
now() { date +%s.%N; }
best1=1e9 best2=1e9
for repeat in 1 2 3; do
  t0=$(now); "$podid" "${args[@]}" -o "$out/one.csv" >/dev/null 2>&1; t1=$(now)
  mpirun --allow-run-as-root --oversubscribe -n 2 "$podid" "${args[@]}" -o "$out/two.csv" >/dev/null 2>&1
  t2=$(now)
  best1=$(awk -v s="$t0" -v e="$t1" -v b="$best1" 'BEGIN { d = e - s; print (d < b) ? d : b }')
  best2=$(awk -v s="$t1" -v e="$t2" -v b="$best2" 'BEGIN { d = e - s; print (d < b) ? d : b }')
done
cmp -s "$out/one.csv" "$out/two.csv" || { echo "the CSVs differ" >&2; exit 1; }
awk -v a="$best1" -v b="$best2" -v n="$points" 'BEGIN {
  printf "landscape, %d points: 1 process %.3f s, 2 ranks %.3f s (best of 3, wall clock, mpirun start-up included): speed-up %.2fx\n", n, a, b, a / b }'
