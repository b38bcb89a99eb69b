#!/usr/bin/env bash
# End-to-end test of `podid cwt`. Usage: bash tests/cli/cwt.sh PODID (from the repo root).
set -u
podid="$1"
data=tests/data/measured_knl50_T1.0.csv
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# A channel: IF statistics, the ridge CSV and the scalogram CSV.
"$podid" cwt "$data" --channel w6 -o "$out/ridge.csv" --scalogram "$out/s.csv" >"$out/stdout" \
  || fail "cwt --channel w6 exited $?"
grep -q "IF inside the cone of influence" "$out/stdout" || fail "no IF statistics"
# The first beam mode is near 33 Hz (hardening: 33-40 Hz).
mean=$(sed -n 's/.*mean \([0-9.]*\) Hz.*/\1/p' "$out/stdout")
awk -v m="$mean" 'BEGIN { exit !(m > 33 && m < 40) }' || fail "mean IF $mean not in 33-40 Hz"
[ "$(head -1 "$out/ridge.csv")" = "t,f_Hz,amplitude,inside_coi" ] || fail "ridge header"
[ "$(wc -l <"$out/ridge.csv")" -eq 5002 ] || fail "ridge rows"
head -1 "$out/s.csv" | grep -q '^t,10Hz,' || fail "scalogram header"

# The first POD time mode, band-limited, max ridge, linear grid.
"$podid" cwt "$data" --pom 1 --band-limited --ridge max --bins 50 -o "$out/pom.csv" >"$out/stdout" \
  || fail "cwt --pom 1 exited $?"
grep -q "POM 1 time mode" "$out/stdout" || fail "no POM label"
[ "$(wc -l <"$out/pom.csv")" -eq 314 ] || fail "band-limited ridge rows"

# The generalised Morse wavelet (MATLAB's default gamma 3, beta 20) sees the same mode.
"$podid" cwt "$data" --channel w6 --wavelet morse >"$out/stdout" || fail "cwt --wavelet morse exited $?"
grep -q "^Morse gamma 3 beta 20 (amplitude)" "$out/stdout" || fail "no Morse description"
mean=$(sed -n 's/.*mean \([0-9.]*\) Hz.*/\1/p' "$out/stdout")
awk -v m="$mean" 'BEGIN { exit !(m > 33 && m < 40) }' || fail "Morse mean IF $mean not in 33-40 Hz"
"$podid" cwt "$data" --channel w6 --wavelet morse --gamma 0.5 2>"$out/stderr"
[ $? -eq 1 ] || fail "gamma 0.5 not exit 1"
grep -q "gamma: expected a value in \[1, 20\], got 0.5" "$out/stderr" || fail "gamma message"
"$podid" cwt "$data" --channel w6 --wavelet mexh 2>"$out/stderr"
[ $? -eq 1 ] || fail "unknown wavelet not exit 1"
grep -q "expected one of morlet, morse" "$out/stderr" || fail "wavelet message"

# Bad input: exit 1 with a one-line message saying what was expected.
"$podid" cwt "$data" --channel w9 2>"$out/stderr" && fail "unknown channel accepted"
[ $? -eq 1 ] || true
grep -q "expected one of w1, w2, w3, w4, w5, w6" "$out/stderr" || fail "channel message"
"$podid" cwt "$data" --channel w6 --fmax 3000 2>"$out/stderr"
[ $? -eq 1 ] || fail "fmax above Nyquist not exit 1"
grep -q "expected <= the Nyquist frequency" "$out/stderr" || fail "Nyquist message"
"$podid" cwt "$data" --channel w6 --ridge greedy 2>"$out/stderr"
[ $? -eq 1 ] || fail "bad ridge method not exit 1"
"$podid" cwt "$data" 2>"$out/stderr"
[ $? -eq 1 ] || fail "neither --channel nor --pom not exit 1"
[ -e "$out/never.csv" ] && fail "output written on error"

# The plot: drawn when gnuplot exists; otherwise (and with PATH emptied) the
# script and data are kept and the command still succeeds.
if command -v gnuplot >/dev/null; then
  "$podid" cwt "$data" --channel w6 --plot "$out/s.png" >/dev/null || fail "plot exited $?"
  [ -s "$out/s.png" ] || fail "no PNG"
  head -c 8 "$out/s.png" | od -c | grep -q "P   N   G" || fail "not a PNG"
  ls "$out" | grep -q "tmp" && fail "temporaries left behind"
fi
PATH=/nonexistent "$podid" cwt "$data" --channel w6 --plot "$out/n.png" -o "$out/r2.csv" \
  >/dev/null 2>"$out/stderr" || fail "plot without gnuplot exited $?"
grep -q "gnuplot not found" "$out/stderr" || fail "no gnuplot message"
[ -s "$out/n.png.gp" ] && [ -s "$out/n.png.data0.txt" ] && [ -s "$out/r2.csv" ] \
  || fail "data not kept without gnuplot"
echo "cli.cwt: ok"
