#!/usr/bin/env bash
# Side-by-side timing of podid's CWT and fCWT (github.com/fastlib/fCWT, the
# fastest public C++ CWT) on fCWT's own benchmark setup: fs 64 Hz, 300
# log-spaced frequencies 1-32 Hz, one thread, full-rate complex output, in
# both tools' two planning configurations:
#   estimated plans (no wisdom: what a first run on a machine gets)
#     fCWT:  single precision, power-of-2 zero padding, FFTW_ESTIMATE (its cwt()).
#     podid: double precision, zero padding (the default) to a 7-smooth length,
#            FFTW_ESTIMATE (BM_CwtFcwtCase/N/1/0 in bench/wavelet_benchmark.cpp).
#   Each tool with the FFTW it is built with: fCWT with its own flags in both
#   its builds, against Debian's libfftw3f (USE_OWN_FFTW=ON: SSE2 and AVX
#   codelets) and, when its tree has them (libs/libfftw3fl.so, Linux), against
#   the FFTW it bundles (its default build: AVX2 codelets too), the faster of
#   the two compared; podid as BUILD_DIR was configured, with the presets
#   build/fftw-simd (scripts/build-fftw.sh: Debian's FFTW source with its AVX2
#   and AVX-512 codelets) when it exists.
#   measured plans (wisdom made once with FFTW_MEASURE, then loaded)
#     fCWT:  its optimisation plans (create_FFT_optimization_plan(N, FFTW_MEASURE),
#            then FCWT(..., use_optimization_plan = true)).
#     podid: FFTW_MEASURE plans kept in its wisdom cache (BM_CwtFcwtCase/N/1/1; the
#            first, discarded run measures them, as `podid plan` does).
#   patient plans (each tool's fastest configuration: the same with FFTW_PATIENT)
#     fCWT:  create_FFT_optimization_plan(N, FFTW_PATIENT).
#     podid: `podid plan --effort patient` for the case, then BM_CwtFcwtCase/N/1/1
#            (which must find every plan in the wisdom: checked).
#   FFTW_PATIENT planning takes minutes (about 1.5 min per tool at 10^4, 1.6 min for
#   fCWT and 5.4 min for podid at 10^5); PLANS="estimated measured" skips it.
# podid is timed twice in each run: with its complex double output, and with
# W rounded to complex float (CwtOutput::kComplexFloat, BM_CwtFcwtCaseComplexFloat:
# the same double-precision transform, fCWT's 8 bytes a coefficient written).
# Both exclude one-time costs (podid's filters; fCWT's output allocation) and
# report the best CPU time (one thread each: CPU time is what the transform
# costs, and it is less disturbed than wall time on a shared machine) of
# several runs, interleaved so both see the same load.
# Usage: FCWT_DIR=/path/to/fCWT [PLANS="estimated measured patient"] \
#          bash bench/compare_fcwt.sh BUILD_DIR [repeats]
# fCWT is not part of podid: without FCWT_DIR the script says so and exits 0.
set -eu
build=${1:?usage: FCWT_DIR=... bash bench/compare_fcwt.sh BUILD_DIR [repeats]}
repeats=${2:-5}
plans_list=${PLANS:-estimated measured patient}
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
  const bool measured = argc > 2 && argv[2][0] == 'm';
  Morlet morlet(1.0f);
  if (argc > 3 && argv[2][0] == 'p') {  // make the optimisation plans (wisdom files here)
    const int flags = argv[3][0] == 'p' ? FFTW_PATIENT : FFTW_MEASURE;
    FCWT(&morlet, 1, true, false).create_FFT_optimization_plan(n, flags);
    return 0;
  }
  std::vector<float> x(n);
  for (int i = 0; i < n; ++i) x[i] = std::cos(2.0 * M_PI * (1.0 + 7.0 * i / n) * (i / 64.0));
  std::vector<std::complex<float>> out(static_cast<std::size_t>(n) * 300);
  double best = 1e9;
  for (int r = 0; r < 3; ++r) {
    timespec t0, t1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    Scales scales(&morlet, FCWT_LOGSCALES, 64, 1.0f, 32.0f, 300);
    FCWT fcwt(&morlet, 1, measured, false);
    fcwt.cwt(x.data(), n, out.data(), &scales);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    best = std::min(best, (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
  }
  std::printf("%.6f\n", best);
}
CPP
# fCWT's own build flags (its CMakeLists.txt: -mavx -O2), one thread.
fcwt_build() {  # "$1": output name, then the FFTW link arguments
  local out=$1
  shift
  g++ -O2 -mavx -fopenmp -std=c++17 -include cassert -include cstring -I"$FCWT_DIR/src/fcwt" \
    "$work/driver.cpp" "$FCWT_DIR/src/fcwt/fcwt.cpp" -o "$work/$out" "$@"
}
fcwt_build fcwt-debian -lfftw3f -lfftw3f_omp
builds=debian
bundled=$FCWT_DIR/libs
if [ -f "$bundled/libfftw3fl.so" ] && [ -f "$bundled/libfftw3f_ompl.so" ]; then
  # Its libraries carry the SONAMEs of Debian's (libfftw3f.so.3, libfftw3f_omp.so.3):
  # links under those names keep the loader from taking Debian's instead.
  mkdir -p "$work/lib"
  ln -s "$bundled/libfftw3fl.so" "$work/lib/libfftw3f.so.3"
  ln -s "$bundled/libfftw3f_ompl.so" "$work/lib/libfftw3f_omp.so.3"
  fcwt_build fcwt-bundled -L"$bundled" -lfftw3fl -lfftw3f_ompl -Wl,-rpath,"$work/lib"
  if ldd "$work/fcwt-bundled" | grep -q "$work/lib/libfftw3f.so.3"; then
    builds="debian bundled"
  else
    echo "compare_fcwt: fCWT's bundled FFTW did not load: timed against Debian's only" >&2
  fi
fi
# One timing: "$1" estimated|measured|patient, "$2" samples; prints the
# seconds of fCWT with Debian's FFTW, with its bundled one (1e9 if not built),
# podid's (complex double output) and podid's with complex float output. Each
# configuration has its own fCWT wisdom folder per build and podid cache.
time_pair() {
  local f b p flag=1 mode=m times=""
  if [ "$1" = estimated ]; then flag=0; mode=e; fi
  for b in debian bundled; do
    f=1e9
    if [[ " $builds " == *" $b "* ]]; then
      mkdir -p "$work/fcwt-$b-$1"
      f=$(cd "$work/fcwt-$b-$1" && "$work/fcwt-$b" "$2" "$mode")
      case "$f" in *[!0-9.]* | "") echo "compare_fcwt: fCWT ($b) printed '$f'" >&2; exit 1 ;; esac
    fi
    times="$times$f "
  done
  p=$(XDG_CACHE_HOME="$work/cache-$1" "$build/bench/wavelet_benchmark" \
      --benchmark_filter="^BM_CwtFcwtCase(ComplexFloat)?/$2/1/$flag/" --benchmark_format=csv 2>/dev/null |
      awk -F, '/^"BM_CwtFcwtCase\// { c = $4 / 1000 } /^"BM_CwtFcwtCaseComplexFloat\// { f = $4 / 1000 }
               END { if (c != "" && f != "") print c, f }')
  [ -n "$p" ] || { echo "compare_fcwt: no BM_CwtFcwtCase(ComplexFloat)/$2/1/$flag result" >&2; exit 1; }
  echo "$times$p"
}
# Wisdom for "$1" measured|patient at "$2" samples, made once outside the timing.
make_wisdom() {
  local b
  for b in $builds; do
    mkdir -p "$work/fcwt-$b-$1"
    (cd "$work/fcwt-$b-$1" && "$work/fcwt-$b" "$2" plan "$1" >/dev/null)
  done
  if [ "$1" = patient ]; then
    # fCWT's case: 300 frequencies from 1 Hz at 60 voices per octave (to 2^(299/60) Hz).
    XDG_CACHE_HOME="$work/cache-patient" "$build/apps/podid" plan --effort patient \
      --samples "$2" --fs 64 --fmin 1 --fmax 31.63 --voices 60 --padding zero >/dev/null
    local before
    before=$(cksum <"$work/cache-patient/podid/fftw3-wisdom")
    time_pair patient "$2" >/dev/null
    if [ "$(cksum <"$work/cache-patient/podid/fftw3-wisdom")" != "$before" ]; then
      echo "compare_fcwt: podid plan --effort patient missed a plan of BM_CwtFcwtCase/$2" >&2
      exit 1
    fi
  else
    time_pair measured "$2" >/dev/null  # the first run measures and caches
  fi
}
printf "%-10s %-8s %14s %14s %12s %8s %14s %8s\n" plans samples "fCWT Debian" "fCWT bundled" "podid (ms)" ratio \
  "podid c64" ratio
for plans in $plans_list; do
  case "$plans" in estimated | measured | patient) ;; *)
    echo "compare_fcwt: PLANS: expected estimated, measured or patient, got '$plans'" >&2; exit 1 ;;
  esac
  for n in 10000 100000; do
    [ "$plans" = estimated ] || make_wisdom "$plans" "$n"
    best="1e9 1e9 1e9 1e9"  # fCWT Debian, fCWT bundled, podid, podid complex float
    for r in $(seq "$repeats"); do
      pair=$(time_pair "$plans" "$n")  # set -e: a failed timing stops the script
      best=$(awk -v a="$best" -v b="$pair" 'BEGIN {
        split(a, x, " "); split(b, y, " ")
        for (i = 1; i <= 4; ++i) printf "%s%s", (y[i] < x[i] ? y[i] : x[i]), (i < 4 ? " " : "\n") }')
    done
    awk -v m="$plans" -v n="$n" -v t="$best" 'BEGIN {
      split(t, x, " "); f = x[1] < x[2] ? x[1] : x[2]
      bundled = x[2] < 1e9 ? sprintf("%14.1f", 1000 * x[2]) : sprintf("%14s", "-")
      printf "%-10s %-8d %14.1f %s %12.1f %7.2fx %14.1f %7.2fx\n", m, n, 1000 * x[1], bundled,
        1000 * x[3], f / x[3], 1000 * x[4], f / x[4] }'
  done
done
echo "fCWT columns: ms with each FFTW; ratio = the faster fCWT's CPU time / podid's (> 1: podid"
echo "faster); podid c64: W computed in double, written as complex float as fCWT writes it;"
echo "best of $repeats interleaved runs"
