#!/usr/bin/env bash
# Side-by-side timing of podid's CWT and fCWT (github.com/fastlib/fCWT, the
# fastest public C++ CWT) on fCWT's own benchmark setup: fs 64 Hz, 300
# log-spaced frequencies 1-32 Hz, one thread, full-rate complex output.
#   fCWT:  single precision, power-of-2 zero padding, FFTW_ESTIMATE plans (its cwt()).
#   podid: double precision, zero padding (the default) to a 7-smooth length, estimated
#          plans (BM_CwtFcwtCase/N/1/0 in bench/wavelet_benchmark.cpp).
# Both exclude one-time costs (podid's filters; fCWT's output allocation) and
# report the best CPU time (one thread each: CPU time is what the transform
# costs, and it is less disturbed than wall time on a shared machine) of
# several runs, interleaved so both see the same load.
# Usage: FCWT_DIR=/path/to/fCWT bash bench/compare_fcwt.sh BUILD_DIR [repeats]
# fCWT is not part of podid: without FCWT_DIR the script says so and exits 0.
set -eu
build=${1:?usage: FCWT_DIR=... bash bench/compare_fcwt.sh BUILD_DIR [repeats]}
repeats=${2:-5}
if [ -z "${FCWT_DIR:-}" ] || [ ! -f "$FCWT_DIR/src/fcwt/fcwt.cpp" ]; then
  echo "compare_fcwt: FCWT_DIR (an fCWT source tree with src/fcwt/fcwt.cpp) not set: skipped"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/driver.cpp" <<'CPP'
#include <cmath>
#include <ctime>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include "fcwt.h"
int main(int argc, char** argv) {
  const int n = std::atoi(argv[1]);
  std::vector<float> x(n);
  for (int i = 0; i < n; ++i) x[i] = std::cos(2.0 * M_PI * (1.0 + 7.0 * i / n) * (i / 64.0));
  std::vector<std::complex<float>> out(static_cast<std::size_t>(n) * 300);
  Morlet morlet(1.0f);
  double best = 1e9;
  for (int r = 0; r < 3; ++r) {
    timespec t0, t1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    Scales scales(&morlet, FCWT_LOGSCALES, 64, 1.0f, 32.0f, 300);
    FCWT fcwt(&morlet, 1, false, false);
    fcwt.cwt(x.data(), n, out.data(), &scales);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    best = std::min(best, (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
  }
  std::printf("%.6f\n", best);
}
CPP
# fCWT's own build flags (its CMakeLists.txt: -mavx -O2), one thread.
g++ -O2 -mavx -fopenmp -std=c++17 -include cassert -include cstring -I"$FCWT_DIR/src/fcwt" \
  "$work/driver.cpp" "$FCWT_DIR/src/fcwt/fcwt.cpp" -o "$work/fcwt" -lfftw3f -lfftw3f_omp
export XDG_CACHE_HOME="$work/cache"  # podid: no wisdom, estimated plans like fCWT
printf "%-8s %12s %12s %8s\n" samples "fCWT (ms)" "podid (ms)" ratio
for n in 10000 100000; do
  best_f=1e9; best_p=1e9
  for r in $(seq "$repeats"); do
    f=$("$work/fcwt" "$n")
    p=$("$build/bench/wavelet_benchmark" --benchmark_filter="BM_CwtFcwtCase/$n/1/0" \
        --benchmark_format=csv 2>/dev/null | awk -F, '/BM_CwtFcwtCase/ { print $4 / 1000 }')
    best_f=$(awk -v a="$best_f" -v b="$f" 'BEGIN { print (b < a ? b : a) }')
    best_p=$(awk -v a="$best_p" -v b="$p" 'BEGIN { print (b < a ? b : a) }')
  done
  awk -v n="$n" -v f="$best_f" -v p="$best_p" \
    'BEGIN { printf "%-8d %12.1f %12.1f %7.2fx\n", n, 1000 * f, 1000 * p, f / p }'
done
echo "ratio = fCWT CPU time / podid CPU time (> 1: podid faster); best of $repeats interleaved runs"
