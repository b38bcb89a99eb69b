#!/usr/bin/env bash
# End-to-end tests of `podid plan` (the FFTW wisdom cache) and of `podid cwt`
# on hostile input (issue 10 item 8b, issue 13 item 1).
# Usage: bash tests/cli/wavelet_engine.sh PODID (from the repo root).
set -u
podid="$1"
data=tests/data/measured_knl50_T1.0.csv
. tests/support/cli.sh
cli_scratch
export XDG_CACHE_HOME="$out/cache"  # never the user's real cache

# plan: measures once into $XDG_CACHE_HOME/podid, then finds the wisdom.
"$podid" plan "$data" >"$out/plan1" || fail "plan exited $?"
# By default both paddings: cwt's zero (9216) and identification's reflect (10240),
# and the full-rate pruned inverses (D x P / D, D a power of 2 up to 64).
grep -q "FFT lengths 9216 real, 10240 real, 9216 complex forward, 10240 complex forward, 576 complex, 640 complex, 9216 complex, 10240 complex, 64 x 144 complex, 64 x 160 complex, 32 x 288 complex, 32 x 320 complex, 16 x 576 complex, 16 x 640 complex" \
  "$out/plan1" || fail "plan lengths"
grep -q "measured 14 plan(s)" "$out/plan1" || fail "first plan did not measure 14"
[ -s "$out/cache/podid/fftw3-wisdom" ] || fail "no wisdom file"
"$podid" plan "$data" >"$out/plan2" || fail "second plan exited $?"
grep -q "measured 0 plan(s) .* 14 already measured" "$out/plan2" || fail "second plan measured again"
ls "$out/cache/podid" | grep -qv '^fftw3-wisdom$' && fail "temporary files left in the cache"
"$podid" cwt "$data" --channel w6 >/dev/null || fail "cwt with wisdom exited $?"
"$podid" plan --samples 5001 2>"$out/stderr"
[ $? -eq 1 ] || fail "--samples without --fs not exit 1"
grep -q "expected --fs HZ" "$out/stderr" || fail "--fs message"
"$podid" plan --samples 3 --fs 100 2>"$out/stderr"
[ $? -eq 1 ] || fail "--samples 3 not exit 1"
# The data options condition DATA files: with --samples alone they were
# silently ignored (the same plans as without them).
for option in "--decimate 4" "--window 0:1" "--rate 5" "--variable x"; do
  # shellcheck disable=SC2086
  "$podid" plan --samples 64 --fs 1000 $option 2>"$out/stderr"
  [ $? -eq 1 ] || fail "plan --samples with $option not exit 1"
  grep -q "plan ${option% *}: expected DATA files to read and condition with it, got --samples alone" \
    "$out/stderr" || fail "plan --samples with $option: $(cat "$out/stderr")"
done
# A given --fs must be a finite rate > 0 (-5 was reported as "no --fs", inf
# as an internal step_s of 0) whose step is finite (1e-320: step inf) and
# within the transforms' steps, 1e-15 .. 1e15 s; --fs without --samples
# plans nothing.
for fs in -5 0 nan inf 1e-320 1e-16 1.1e15; do
  "$podid" plan --samples 999 --fs "$fs" 2>"$out/stderr"
  [ $? -eq 1 ] || fail "--fs $fs not exit 1"
  grep -q "plan --fs: expected a sampling frequency between 1e-15 Hz and 1e15 Hz, got" \
    "$out/stderr" || fail "--fs $fs message: $(cat "$out/stderr")"
done
# A file's step outside that range: the error names the file.
awk -F, 'NR == 1 { print; next } { printf "%.12e", $1 * 1e-12; for (c = 2; c <= NF; c++) printf ",%s", $c; print "" }' \
  "$data" >"$out/tiny_step.csv"
"$podid" plan "$out/tiny_step.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "plan of a 2e-16 s step not exit 1"
grep -q "^podid: error: $out/tiny_step.csv: FFT lengths: step_s: expected a finite value between 1e-15 s and 1e15 s, got 2e-16" \
  "$out/stderr" || fail "plan of a 2e-16 s step: $(cat "$out/stderr")"
# The same rule for cwt's --step and --rate: a subnormal step's rate is inf.
"$podid" cwt "$data" --channel w6 --step 1e-320 -o "$out/sub.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "cwt --step 1e-320 not exit 1"
grep -q -- "--step: expected a finite sampling step > 0 s with a finite rate 1 / step" "$out/stderr" ||
  fail "cwt --step 1e-320: $(cat "$out/stderr")"
[ ! -e "$out/sub.csv" ] || fail "cwt --step 1e-320 wrote output"
"$podid" plan "$data" --fs 1000 2>"$out/stderr"
[ $? -eq 1 ] || fail "--fs without --samples not exit 1"
grep -q "expected --samples N" "$out/stderr" || fail "--fs without --samples: $(cat "$out/stderr")"
# DATA is read as cwt reads it: --decimate 2 halves the record (5001 -> 2501
# samples), so cwt's zero padding plans 4608 points instead of 9216.
"$podid" plan "$data" --decimate 2 --padding zero >"$out/plan7" || fail "plan --decimate exited $?"
grep -q "FFT lengths 4608 real" "$out/plan7" || fail "plan --decimate: $(cat "$out/plan7")"
# plan takes cwt's wavelet and grid options: Morse gamma 3 beta 20 lasts
# longer than Morlet omega0 6 (its cone is 1.30x Morlet's at a frequency; at
# 10 Hz its support is longer than the 1 s record), so cwt --wavelet morse
# pads 5001 samples to 12288 points, not 9216; planned once, its plans are
# found.
"$podid" plan "$data" --padding zero --wavelet morse >"$out/morse1" || fail "plan --wavelet morse exited $?"
grep -q "FFT lengths 12288 real, 12288 complex forward, 512 complex, 12288 complex, 64 x 192 complex" \
  "$out/morse1" || fail "plan --wavelet morse: $(cat "$out/morse1")"
"$podid" plan "$data" --padding zero --wavelet morse >"$out/morse2" || fail "second plan --wavelet morse exited $?"
grep -q "measured 0 plan(s)" "$out/morse2" || fail "Morse plans measured again: $(cat "$out/morse2")"
"$podid" plan "$data" --padding zero --bins 100 --voices 12 2>"$out/stderr"
[ $? -eq 1 ] || fail "plan --bins with --voices not exit 1"
"$podid" plan "$data" --padding zero --normalisation l2 2>"$out/stderr"
[ $? -eq 1 ] || fail "plan --normalisation l2 not exit 1"
grep -q -- "--normalisation: expected one of amplitude, energy, got \"l2\"" "$out/stderr" ||
  fail "--normalisation message: $(cat "$out/stderr")"
"$podid" plan --samples 999 --fs 1000 --effort fast 2>"$out/stderr"
[ $? -eq 1 ] || fail "--effort fast not exit 1"
grep -q -- '--effort: expected one of measure, patient, got "fast"' "$out/stderr" ||
  fail "--effort message: $(cat "$out/stderr")"
# --samples: every item a length (CLI11's delimiter dropped empty items).
for bad in "1000,,2000" "1000," "1e9" "abc"; do
  "$podid" plan --samples "$bad" --fs 1000 2>"$out/stderr"
  [ $? -eq 1 ] || fail "plan --samples $bad not exit 1"
  grep -q -- "--samples: expected record lengths N\[,N...\]" "$out/stderr" ||
    fail "--samples $bad message: $(cat "$out/stderr")"
done
# CLI11's own wording, told as podid's "expected X, got Y".
"$podid" plan --samples 999 --fs 1000 --fs 2000 2>"$out/stderr"
[ $? -eq 1 ] || fail "--fs twice not exit 1"
grep -q -- "--fs: expected one value (the option given once), got 2" "$out/stderr" ||
  fail "--fs twice message: $(cat "$out/stderr")"
"$podid" plan --samples 999 --fs 1kHz 2>"$out/stderr"
[ $? -eq 1 ] || fail "--fs 1kHz not exit 1"
grep -q -- '--fs: expected a number, got "1kHz"' "$out/stderr" ||
  fail "--fs 1kHz message: $(cat "$out/stderr")"
# --effort patient measures again what FFTW_MEASURE wisdom covers (FFTW_PATIENT
# is more rigorous), then finds it.
"$podid" plan --samples 64 --fs 1000 --fmin 100 --fmax 400 --padding zero >"$out/plan4" ||
  fail "plan 64 exited $?"
"$podid" plan --samples 64 --fs 1000 --fmin 100 --fmax 400 --padding zero --effort patient \
  >"$out/plan5" || fail "plan --effort patient exited $?"
grep -q "measured [1-9][0-9]* plan(s) (FFTW_PATIENT)" "$out/plan5" || fail "patient: $(cat "$out/plan5")"
"$podid" plan --samples 64 --fs 1000 --fmin 100 --fmax 400 --padding zero --effort patient \
  >"$out/plan6" || fail "second plan --effort patient exited $?"
grep -q "measured 0 plan(s) (FFTW_PATIENT)" "$out/plan6" || fail "patient again: $(cat "$out/plan6")"
# The cache is plan's output: one it cannot write is an error (exit 1, on
# stderr), found before measuring (it used to measure, print "wisdom not
# saved" on stdout and exit 0). cwt only reads the cache: never an error.
plan_refused() {  # plan_refused WHAT NEEDLE [env assignments...]
  local what=$1 needle=$2
  shift 2
  env "$@" "$podid" plan --samples 999 --fs 1000 --fmin 20 --fmax 400 >"$out/plan3" 2>"$out/stderr"
  local rc=$?
  [ $rc -eq 1 ] || fail "plan, $what: exit $rc, expected 1"
  grep -q -- "^podid: error: plan: wisdom cache: $needle" "$out/stderr" ||
    fail "plan, $what: $(cat "$out/stderr")"
  [ ! -s "$out/plan3" ] || fail "plan, $what: measured before refusing: $(cat "$out/plan3")"
}
plan_refused "a cache under /proc" "expected a writable folder" XDG_CACHE_HOME=/proc/podid-no-such-dir
printf 'x\n' >"$out/cache_file"
plan_refused "XDG_CACHE_HOME a file" "expected a folder (or a path to create one), got \"$out/cache_file/podid\": $out/cache_file is not a folder" \
  XDG_CACHE_HOME="$out/cache_file"
mkdir -p "$out/dir_cache/podid/fftw3-wisdom"
plan_refused "the wisdom file a folder" "expected a file (or none yet), got \"$out/dir_cache/podid/fftw3-wisdom\", a folder" \
  XDG_CACHE_HOME="$out/dir_cache"
plan_refused "no HOME, no XDG_CACHE_HOME" "expected XDG_CACHE_HOME (an absolute path) or HOME set" \
  -u HOME -u XDG_CACHE_HOME
# ...and one that fails after measuring (a full disk: RLIMIT_FSIZE 0 with
# SIGXFSZ ignored, so write() fails with EFBIG) too, on stderr.
message=$(
  export XDG_CACHE_HOME="$out/full_cache"
  ulimit -f 0
  trap '' XFSZ
  exec "$podid" plan --samples 999 --fs 1000 --fmin 20 --fmax 400 2>&1 >/dev/null
)
rc=$?
[ $rc -eq 1 ] || fail "plan on a full disk: exit $rc, expected 1 ($message)"
echo "$message" | grep -q "^podid: error: plan: wisdom not saved to $out/full_cache/podid/fftw3-wisdom: .*plan(s) measured are lost" ||
  fail "plan on a full disk: $message"
XDG_CACHE_HOME="$out/cache_file" "$podid" cwt "$data" --channel w6 >/dev/null 2>"$out/stderr" ||
  fail "cwt with XDG_CACHE_HOME a file exited $?: $(cat "$out/stderr")"
# A cache file FFTW's own reader would hang on (a FIFO) is ignored, named, replaced.
mkdir -p "$out/fifo/podid" && mkfifo "$out/fifo/podid/fftw3-wisdom"
XDG_CACHE_HOME="$out/fifo" timeout 60 "$podid" cwt "$data" --channel w6 >/dev/null ||
  fail "cwt with a FIFO as the cache exited $?"
XDG_CACHE_HOME="$out/fifo" timeout 60 "$podid" plan --samples 999 --fs 1000 >"$out/plan8" ||
  fail "plan with a FIFO as the cache exited $?"
grep -q "wisdom cache ignored: $out/fifo/podid/fftw3-wisdom: not a regular file (replaced)" \
  "$out/plan8" || fail "FIFO cache: $(cat "$out/plan8")"
[ -f "$out/fifo/podid/fftw3-wisdom" ] || fail "FIFO cache not replaced by a file"

# cwt: any finite amplitude gives the tone's IF (1e300 aborted, 1e200 crashed).
for amplitude in 1e300 1e200 1e-150; do
  awk -v a="$amplitude" 'BEGIN { print "t,x"; for (i = 0; i <= 5000; ++i) {
    t = i / 5000; printf "%.17g,%.17g\n", t, a * cos(2 * 3.141592653589793 * 33 * t) } }' \
    >"$out/tone.csv"
  # reflect padding continues the 33 whole periods exactly: the IF is 33 Hz to rounding.
  "$podid" cwt "$out/tone.csv" --channel x --padding reflect >"$out/stdout" 2>&1 \
    || fail "cwt amplitude $amplitude exited $?"
  grep -q "mean 33 Hz" "$out/stdout" || fail "amplitude $amplitude: $(grep mean "$out/stdout")"
done
# --bins is bounded by memory before allocating (was 8 GB then bad_alloc).
start=$(date +%s)
"$podid" cwt "$data" --channel w6 --bins 100000 2>"$out/stderr"
[ $? -eq 1 ] || fail "--bins 100000 not exit 1"
# (the streamed ridge's estimate: 4-byte back-pointers beyond 65535 frequencies)
grep -q "RidgeFrequency: memory: expected at most 2147483648 bytes" "$out/stderr" || fail "memory message"
"$podid" cwt "$data" --channel w6 --bins 100000 --scalogram "$out/big.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--bins 100000 --scalogram not exit 1"
grep -q "Cwt: memory: expected at most 954437176 bytes" "$out/stderr" || fail "whole-transform memory message"
[ -e "$out/big.csv" ] && fail "a refused transform wrote --scalogram"
[ $(( $(date +%s) - start )) -le 5 ] || fail "--bins 100000 took more than 5 s"
# --bins 0 and below were taken for "no --bins" (the log grid, exit 0).
for bins in 0 -5; do
  "$podid" cwt "$data" --channel w6 --bins "$bins" -o "$out/bins.csv" 2>"$out/stderr"
  [ $? -eq 1 ] || fail "--bins $bins not exit 1"
  grep -q -- "--bins: expected an integer in \[2, 100000\], got \"$bins\"" "$out/stderr" || fail "--bins $bins message"
done
[ -e "$out/bins.csv" ] && fail "a refused --bins wrote -o"
# A scalogram wider than ReadCsv's lines (1 MiB; 60,000 frequencies print
# 1,140,018 bytes a row) is refused, not written unreadable.
awk 'BEGIN { print "t,x"; for (i = 0; i < 200; ++i) printf "%.17g,%.17g\n", i / 5000, cos(0.0628 * i) }' \
  >"$out/short.csv"
"$podid" cwt "$out/short.csv" --channel x --bins 60000 --scalogram "$out/wide.csv" \
  >/dev/null 2>"$out/stderr"
[ $? -eq 1 ] || fail "--bins 60000 --scalogram not exit 1"
grep -q "expected lines of at most 1048576 bytes (kMaxCsvLineBytes, what ReadCsv reads back)" \
  "$out/stderr" || fail "wide scalogram message: $(cat "$out/stderr")"
[ -e "$out/wide.csv" ] && fail "a refused scalogram was written"
"$podid" cwt "$data" --channel w6 --bins 2000 --max-memory 100 2>"$out/stderr"
[ $? -eq 1 ] || fail "--max-memory 100 not exit 1"
"$podid" cwt "$data" --channel w6 --threads 2 >"$out/t2" || fail "--threads 2 exited $?"
"$podid" cwt "$data" --channel w6 >"$out/t1" || fail "cwt exited $?"
cmp -s "$out/t1" "$out/t2" || fail "--threads 2 changed the output"
echo "wavelet_engine: ok"
