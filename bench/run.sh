#!/bin/sh
# Build the release benchmarks and run them all, keeping the JSON results in
# bench/results/<name>_<machine>.json, then the Python comparisons.
#
# Usage (from anywhere): bench/run.sh [MACHINE [NAME...]]
#   MACHINE default: hostname; NAMEs (simulate ident pod wavelet ...) default:
#   every bench/*_benchmark.cpp. The Python comparisons run with simulate, ident
#   and wavelet (compare_pywt.py).
# Environment: BUILD_DIR (default build/bench), JOBS (default 2),
#   RESULTS (default bench/results),
#   PIN (default "taskset -c 0": the one-core figures; set PIN= to not pin).
# The landscape benchmark (BM_LandscapeWavelet1s) is run unpinned: its target
# is the wall time on all cores.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
machine=${1:-$(hostname)}
[ $# -gt 0 ] && shift
if [ $# -gt 0 ]; then names="$*"; else
  names=$(for f in bench/*_benchmark.cpp; do basename "$f" _benchmark.cpp; done)
fi
build=${BUILD_DIR:-build/bench}
jobs=${JOBS:-2}
pin=${PIN-taskset -c 0}
results=${RESULTS:-bench/results}
mkdir -p "$results"

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPODID_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target podid_cli \
  $(for name in $names; do echo "${name}_benchmark"; done)

echo "machine: $machine, $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
echo "load before: $(uptime)"
common="--benchmark_repetitions=5 --benchmark_report_aggregates_only=true --benchmark_out_format=json"
for name in $names; do
  exe="$build/bench/${name}_benchmark"
  if [ "$name" = ident ]; then
    # One-core evaluations pinned; the landscape on every core.
    $pin "$exe" $common --benchmark_filter='BM_Evaluate' \
      --benchmark_out="$results/ident_${machine}.json"
    "$exe" $common --benchmark_filter='BM_Landscape' \
      --benchmark_out="$results/ident_landscape_${machine}.json"
  else
    $pin "$exe" $common --benchmark_out="$results/${name}_${machine}.json"
  fi
done
echo "load after: $(uptime)"

# Python peers (Debian's numpy, scipy, pywt), ratios measured in this run.
for name in $names; do
  case $name in
    simulate) script=compare_python_simulate.py ;;
    ident) script=compare_python_ident.py ;;
    wavelet) script=compare_pywt.py ;;
    *) continue ;;
  esac
  [ -f "bench/$script" ] || continue
  $pin /usr/bin/python3 "bench/$script" "$build" | tee "$results/${script%.py}_${machine}.txt"
done
