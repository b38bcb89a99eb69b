#!/usr/bin/env bash
# Builds the libFuzzer targets in build/fuzz (clang++-14) and runs each for the
# given number of seconds, one after the other.
# Usage: bash fuzz/run.sh [seconds=60] [csv|case|mat|uff|model|wisdom ...]
#   The growing corpus is build/fuzz/corpus/<target> (the committed seeds in
#   fuzz/corpus/<target> are read, never written); crashes land in
#   build/fuzz/artifacts/<target>/. Exits non-zero when a target finds one.
#   PODID_FUZZ_JOBS=2 runs two targets at once; PODID_FUZZ_BUILD sets the build folder.
#   PODID_FUZZ_RUNS=N (with PODID_FUZZ_SEED, default 1) makes each run N inputs
#   from that seed instead of running for the given seconds: the same inputs on
#   every machine with the same compilers, as CI needs (.ci/fuzz-smoke.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
if ((${#targets[@]} == 0)); then targets=(csv case mat uff model wisdom); fi
build="${PODID_FUZZ_BUILD:-build/fuzz}"

# Line tables only (-g1): the reports keep file:line, the build takes about a
# third less time than with full debug info.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DCMAKE_CXX_COMPILER=clang++-14 -DPODID_BUILD_FUZZERS=ON \
  -DPODID_BUILD_TESTS=OFF -DPODID_BUILD_BENCH=OFF -DPODID_BUILD_APPS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/podid_fuzz_}"

# ASan keeps freed memory of libmatio/HDF5 mapped: release it so that the RSS
# limit catches real growth; -malloc_limit_mb flags any single allocation the
# input makes podid (or matio) request beyond 2 GB.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:allocator_release_to_os_interval_ms=500}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
run_one() {
  local target="$1" rc=0
  mkdir -p "$build/corpus/$target" "$build/artifacts/$target"
  local budget=(-max_total_time="$seconds") what="${seconds} s"
  if [[ -n "${PODID_FUZZ_RUNS:-}" ]]; then
    budget=(-runs="$PODID_FUZZ_RUNS" -seed="${PODID_FUZZ_SEED:-1}")
    what="$PODID_FUZZ_RUNS runs from seed ${PODID_FUZZ_SEED:-1}"
  fi
  echo "fuzz: $target for $what"
  local dict=()
  if [[ -f "fuzz/$target.dict" ]]; then dict=(-dict="fuzz/$target.dict"); fi
  "$build/fuzz/podid_fuzz_$target" "$build/corpus/$target" "fuzz/corpus/$target" \
    "${budget[@]}" "${dict[@]}" -timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$target/" \
    >"$build/$target.log" 2>&1 || rc=$?
  grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|^Done|ERROR' \
    "$build/$target.log" | sed "s/^/fuzz: $target: /" || true
  return $rc
}
status=0
jobs="${PODID_FUZZ_JOBS:-1}"
pids=()
for target in "${targets[@]}"; do
  run_one "$target" &
  pids+=($!)
  if ((${#pids[@]} >= jobs)); then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
if ((status != 0)); then echo "fuzz: a target failed; see $build/*.log and $build/artifacts/"; fi
exit $status
