#!/usr/bin/env bash
# End-to-end test of `podid cwt`. Usage: bash tests/cli/cwt.sh PODID (from the repo root).
set -u
podid="$1"
data=tests/data/measured_knl50_T1.0.csv
. tests/support/cli.sh
cli_scratch

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
# Without --scalogram the ridge is streamed in blocks: the same ridge as the
# whole transform's, to 1e-9 relative (the blocks' W agree to the band
# tolerance 1e-12 of the peak; the IF's phase derivative amplifies that where
# |W| is small, far from the 1e-9 this allows).
"$podid" cwt "$data" --channel w6 -o "$out/streamed.csv" >/dev/null || fail "streamed cwt exited $?"
paste -d, "$out/ridge.csv" "$out/streamed.csv" | tail -n +2 | awk -F, '
  function d(a, b) { return (a == b) ? 0 : (a - b < 0 ? b - a : a - b) / ((a < 0 ? -a : a) + 1e-300) }
  { for (c = 1; c <= 4; c++) if (d($c, $(c + 4)) > 1e-9) { print "row " NR " column " c ": " $c " vs " $(c + 4); bad = 1; exit } }
  END { exit bad }' || fail "streamed ridge differs from the whole transform's"
# The ridge CSV's time is the record's: a record starting at t = 0.25 s gives
# the same ridge, 0.25 s later.
awk -F, 'NR == 1 { print; next } { printf "%.10f", $1 + 0.25; for (c = 2; c <= NF; c++) printf ",%s", $c; print "" }' \
  "$data" >"$out/late.csv"
"$podid" cwt "$out/late.csv" --channel w6 -o "$out/late_ridge.csv" >/dev/null || fail "late cwt exited $?"
paste -d, "$out/streamed.csv" "$out/late_ridge.csv" | tail -n +2 | awk -F, '
  { dt = $5 - $1 - 0.25; if (dt < -1e-9 || dt > 1e-9 || $2 != $6) { print "row " NR ": " $0; bad = 1; exit } }
  END { exit bad }' || fail "a record starting at 0.25 s: ridge time not shifted by 0.25 s"

# The first POD time mode, band-limited, max ridge, linear grid.
"$podid" cwt "$data" --pom 1 --band-limited --ridge max --bins 50 -o "$out/pom.csv" >"$out/stdout" \
  || fail "cwt --pom 1 exited $?"
grep -q "POM 1 time mode" "$out/stdout" || fail "no POM label"
[ "$(wc -l <"$out/pom.csv")" -eq 314 ] || fail "band-limited ridge rows"

# Two ridges of a two-tone signal (20 Hz, and 60 Hz at half the amplitude):
# ridge 1 is the stronger tone, ridge 2 the other, each to 0.1 Hz.
awk 'BEGIN { print "t,x"; for (i = 0; i <= 2000; i++) { t = i / 1000;
  printf "%.6f,%.12f\n", t, cos(2 * 3.141592653589793 * 20 * t) + 0.5 * cos(2 * 3.141592653589793 * 60 * t) } }' \
  >"$out/two.csv"
"$podid" cwt "$out/two.csv" --channel x --ridges 2 -o "$out/two_ridges.csv" >"$out/stdout" \
  || fail "cwt --ridges 2 exited $?"
means=$(sed -n 's/.*mean \([0-9.]*\) Hz.*/\1/p' "$out/stdout" | tr '\n' ' ')
awk -v m="$means" 'BEGIN { split(m, v, " "); exit !(v[1] > 19.9 && v[1] < 20.1 && v[2] > 59.9 && v[2] < 60.1) }' \
  || fail "two ridges' mean IFs $means, expected 20 and 60 Hz"
[ "$(head -1 "$out/two_ridges.csv")" = "t,f_Hz,amplitude,inside_coi,f_Hz2,amplitude2,inside_coi2" ] \
  || fail "two-ridge header"
"$podid" cwt "$data" --channel w6 --ridges 17 2>"$out/stderr"
[ $? -eq 1 ] || fail "--ridges 17 not exit 1"
grep -q -- '--ridges: expected an integer in \[1, 16\], got "17"' "$out/stderr" || fail "ridges message"

# The synchrosqueezed transform's ridges (--synchrosqueeze): on the chirp
# f = 20 + 30 t Hz the worst IF error inside the cone is no larger than the
# CWT ridge's (0.035 against 0.037 Hz); the two tones give ridges at 20 Hz
# (to 1e-3 Hz) and 60 Hz (to 0.03 Hz: the 20 Hz tone's leak into the 60 Hz
# scales, 40 Hz x 2 e^-8 = 0.027 Hz, moves the CWT ridge as much) in 0.3-1.7 s.
awk 'BEGIN { print "t,x"; for (i = 0; i <= 2000; i++) { t = i / 1000;
  printf "%.6f,%.12f\n", t, cos(2 * 3.141592653589793 * (20 * t + 15 * t * t)) } }' >"$out/chirp.csv"
"$podid" cwt "$out/chirp.csv" --channel x -o "$out/chirp_cwt.csv" >/dev/null || fail "chirp cwt exited $?"
"$podid" cwt "$out/chirp.csv" --channel x --synchrosqueeze -o "$out/chirp_sst.csv" \
  --scalogram "$out/chirp_T.csv" >"$out/stdout" || fail "cwt --synchrosqueeze exited $?"
grep -q "on the synchrosqueezed |T|" "$out/stdout" || fail "no synchrosqueezed ridge line"
grep -q "^|T| -> " "$out/stdout" || fail "no |T| scalogram"
worst_if() { awk -F, 'NR > 1 && $4 == 1 { e = $2 - (20 + 30 * $1); if (e < 0) e = -e; if (e > m) m = e }
  END { print m + 0 }' "$1"; }
w_cwt=$(worst_if "$out/chirp_cwt.csv"); w_sst=$(worst_if "$out/chirp_sst.csv")
awk -v c="$w_cwt" -v s="$w_sst" 'BEGIN { exit !(s <= c && s < 0.05) }' \
  || fail "SST ridge's worst IF error $w_sst Hz, CWT ridge's $w_cwt Hz"
"$podid" cwt "$out/two.csv" --channel x --ridges 2 --synchrosqueeze -o "$out/two_sst.csv" >/dev/null \
  || fail "two tones --synchrosqueeze exited $?"
awk -F, 'NR > 1 && $1 >= 0.3 && $1 <= 1.7 { n++
  if ($2 < 19.999 || $2 > 20.001 || $5 < 59.97 || $5 > 60.03) { print "t " $1 ": " $2 ", " $5; bad = 1; exit } }
  END { exit bad || n < 1300 }' "$out/two_sst.csv" || fail "SST ridges of two tones"
# One tone, two SST ridges: outside the first ridge's exclusion |T| is 0, so
# the second ridge has no cell at some times; those rows say nan (this
# crashed with a segmentation fault before).
awk 'BEGIN { print "t,x"; for (i = 0; i <= 2000; i++) { t = i / 1000;
  printf "%.6f,%.12f\n", t, cos(2 * 3.141592653589793 * 40 * t) } }' >"$out/tone.csv"
"$podid" cwt "$out/tone.csv" --channel x --ridges 2 --synchrosqueeze -o "$out/tone_sst.csv" >/dev/null \
  || fail "one tone, --ridges 2 --synchrosqueeze exited $?"
[ "$(wc -l <"$out/tone_sst.csv")" -eq 2002 ] || fail "one tone, two SST ridges: rows"
awk -F, 'NR > 1 && tolower($5) == "nan" { n++ } END { exit n < 1 }' "$out/tone_sst.csv" \
  || fail "one tone, two SST ridges: no nan row in the second ridge"
# W (then T in its place), the reassignment field and the ridge search's
# cost and back-pointer: 36 bytes a cell for W's 16. W's share, with the
# filters and FFT buffers, is 10.09 MB (5001 x 115 cells): 22.7 MB (21.6 MiB)
# in all with --synchrosqueeze, 17.7 MB (16.8 MiB) for W and the search.
"$podid" cwt "$data" --channel w6 --synchrosqueeze --max-memory 20 2>"$out/stderr"
[ $? -eq 1 ] || fail "--synchrosqueeze in 20 MB not exit 1"
grep -q "\[--max-memory 20 MB x 16 / 36: W's share of the 36 bytes a coefficient takes with --synchrosqueeze, the ridge search\]" \
  "$out/stderr" || fail "SST memory message: $(cat "$out/stderr")"
# The smallest limit: W's share of 1 MB is a budget, not a bad option.
"$podid" cwt "$data" --channel w6 --synchrosqueeze --scalogram "$out/sc1.csv" --max-memory 1 \
  2>"$out/stderr"
[ $? -eq 1 ] || fail "--synchrosqueeze --scalogram in 1 MB not exit 1"
grep -q "\[--max-memory 1 MB x 16 / 44: W's share" "$out/stderr" \
  || fail "1 MB memory message: $(cat "$out/stderr")"
[ ! -e "$out/sc1.csv" ] || fail "a refused transform wrote its scalogram"
# The refusal names this command's options, not the library's fields.
"$podid" cwt "$data" --channel w6 --ridges 2 --max-memory 1 2>"$out/stderr"
[ $? -eq 1 ] || fail "--ridges 2 in 1 MB not exit 1"
grep -q "expected at most 599186 bytes (--max-memory), got .*a higher --fmin or --band-limited) \[--max-memory 1 MB x 16 / 28: W's share of the 28 bytes a coefficient takes with the ridge search\]$" \
  "$out/stderr" || fail "whole-transform memory message: $(cat "$out/stderr")"
"$podid" cwt "$data" --channel w6 --max-memory 1 2>"$out/stderr"
[ $? -eq 1 ] || fail "streamed ridge in 1 MB not exit 1"
grep -q "(--max-memory), got .*fewer frequencies or --band-limited)$" "$out/stderr" \
  || fail "streamed memory message: $(cat "$out/stderr")"
"$podid" cwt "$data" --channel w6 --ridges 2 --max-memory 16 2>/dev/null >/dev/null \
  && fail "W and the ridge search (16.8 MiB) in 16 MB"
"$podid" cwt "$data" --channel w6 --ridges 2 --max-memory 17 >/dev/null \
  || fail "W and the ridge search in 17 MB failed"
"$podid" cwt "$data" --channel w6 --synchrosqueeze --max-memory 22 -o "$out/sst22.csv" >/dev/null \
  || fail "--synchrosqueeze in 22 MB failed"

# --inverse: the in-band part of each signal (the inverse CWT). x = a 30 Hz
# tone plus a 300 Hz one far above the 10-120 Hz grid, y = a 45 Hz tone: the
# in-band parts are the 30 and 45 Hz tones, within 1e-3 RMS (the issue's
# reconstruction bound; 1.3e-5 and 2.1e-4 measured) in 0.3-1.7 s.
awk 'BEGIN { print "t,x,y"; for (i = 0; i <= 2000; i++) { t = i / 1000; pi = 3.141592653589793
  printf "%.6f,%.12f,%.12f\n", t, cos(2 * pi * 30 * t) + 0.7 * cos(2 * pi * 300 * t + 0.4), sin(2 * pi * 45 * t) } }' \
  >"$out/bands.csv"
"$podid" cwt "$out/bands.csv" --channel all --inverse "$out/in_band.csv" >"$out/stdout" \
  || fail "cwt --inverse exited $?"
grep -q "^in-band signal -> " "$out/stdout" || fail "no in-band line"
[ "$(head -1 "$out/in_band.csv")" = "t,x,y" ] || fail "in-band header"
awk -F, 'NR > 1 && $1 >= 0.3 && $1 <= 1.7 { pi = 3.141592653589793
  e = $2 - cos(2 * pi * 30 * $1); f = $3 - sin(2 * pi * 45 * $1); se += e * e; sf += f * f; n++ }
  END { exit !(n > 1300 && sqrt(se / n) < 1e-3 && sqrt(sf / n) < 1e-3) }' "$out/in_band.csv" \
  || fail "in-band parts not the 30 and 45 Hz tones within 1e-3"

# Every channel in one call: the same IF as one channel at a time.
"$podid" cwt "$data" --channel all --band-limited -o "$out/all.csv" >"$out/stdout" \
  || fail "cwt --channel all exited $?"
[ "$(grep -c "IF inside the cone" "$out/stdout")" -eq 6 ] || fail "not 6 channels"
head -1 "$out/all.csv" | grep -q '^t,w1_f_Hz,w1_amplitude,w1_inside_coi,w2_f_Hz,.*,w6_inside_coi$' \
  || fail "all-channel header"
"$podid" cwt "$data" --channel w3 --band-limited -o "$out/w3.csv" >/dev/null || fail "w3 exited $?"
[ "$(cut -d, -f2-4 "$out/w3.csv" | tail -n +2)" = "$(cut -d, -f8-10 "$out/all.csv" | tail -n +2)" ] \
  || fail "--channel all's w3 columns differ from --channel w3"
# The kept ridges are bounded by --max-memory too (6 x 16 x 313 x 64 bytes =
# 1.8 MiB; the transform with its ridge search needs 1.35 MiB of the 1.5).
"$podid" cwt "$data" --channel all --ridges 16 --band-limited --max-memory 1.5 2>"$out/stderr"
[ $? -eq 1 ] || fail "16 ridges of 6 channels in 1.5 MB not exit 1"
grep -q "expected at least 2 MB for 6 channels x 16 ridges x 313 output times, got 1.5 MB" "$out/stderr" \
  || fail "ridge memory message: $(cat "$out/stderr")"
"$podid" cwt "$data" --channel all --plot "$out/all.png" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--channel all --plot not exit 1"
grep -q "expected a single --channel or --pom" "$out/stderr" || fail "all + plot message"

# Scale conventions: with energy normalisation, MATLAB's / PyWavelets' peak
# labels (omega0 / (2 pi s)) sit 6 / 6.0822 below Torrence & Compo's ridge labels.
"$podid" cwt "$data" --channel w6 --normalisation energy --scalogram "$out/ridge_labels.csv" >/dev/null \
  || fail "ridge convention exited $?"
"$podid" cwt "$data" --channel w6 --normalisation energy --scale-convention peak \
  --scalogram "$out/peak_labels.csv" >/dev/null || fail "peak convention exited $?"
# The label of the largest |W| at t = 0.5 s: 1.35 % lower under peak (within a 2.2 % bin).
argmax() { awk -F, 'NR == 1 { for (i = 2; i <= NF; i++) h[i] = $i + 0 }
  NR == 2502 { b = 2; for (i = 2; i <= NF; i++) if ($i > $b) b = i; print h[b] }' "$1"; }
fr=$(argmax "$out/ridge_labels.csv"); fp=$(argmax "$out/peak_labels.csv")
awk -v r="$fr" -v p="$fp" 'BEGIN { q = p / r; exit !(q < 1.0 && q > 0.96) }' \
  || fail "peak label $fp Hz not 1-4 % below ridge label $fr Hz"
"$podid" cwt "$data" --channel w6 --scale-convention matlab 2>"$out/stderr"
[ $? -eq 1 ] || fail "bad convention not exit 1"
grep -q -- "--scale-convention: expected one of ridge, peak" "$out/stderr" || fail "convention message"

# The generalised Morse wavelet (MATLAB's default gamma 3, beta 20) sees the same mode.
"$podid" cwt "$data" --channel w6 --wavelet morse >"$out/stdout" || fail "cwt --wavelet morse exited $?"
grep -q "^Morse gamma 3 beta 20 (amplitude)" "$out/stdout" || fail "no Morse description"
mean=$(sed -n 's/.*mean \([0-9.]*\) Hz.*/\1/p' "$out/stdout")
awk -v m="$mean" 'BEGIN { exit !(m > 33 && m < 40) }' || fail "Morse mean IF $mean not in 33-40 Hz"
"$podid" cwt "$data" --channel w6 --wavelet morse --gamma 0.5 2>"$out/stderr"
[ $? -eq 1 ] || fail "gamma 0.5 not exit 1"
grep -q -- '--gamma: expected a number in \[1, 20\], got "0.5"' "$out/stderr" || fail "gamma message"
"$podid" cwt "$data" --channel w6 --wavelet mexh 2>"$out/stderr"
[ $? -eq 1 ] || fail "unknown wavelet not exit 1"
grep -q -- "--wavelet: expected one of morlet, morse" "$out/stderr" || fail "wavelet message"

# Bad input: exit 1 with a one-line message saying what was expected.
"$podid" cwt "$data" --channel w9 2>"$out/stderr" && fail "unknown channel accepted"
[ $? -eq 1 ] || true
grep -q "expected one of w1, w2, w3, w4, w5, w6 or all" "$out/stderr" || fail "channel message"
"$podid" cwt "$data" --channel w6 --fmax 3000 2>"$out/stderr"
[ $? -eq 1 ] || fail "fmax above Nyquist not exit 1"
grep -q -- "--fmax: expected at most the Nyquist frequency of $data as read, 2500 Hz (step 0.0002 s), got 3000 Hz" \
  "$out/stderr" || fail "Nyquist message: $(cat "$out/stderr")"
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
# Without gnuplot the script and data go to a new folder: a file that has the
# names they once had (here the case's copy) is not replaced.
cp examples/beam.toml "$out/n.png.gp"
PATH=/nonexistent "$podid" cwt "$data" --channel w6 --plot "$out/n.png" -o "$out/r2.csv" \
  >/dev/null 2>"$out/stderr" || fail "plot without gnuplot exited $?"
grep -q "gnuplot not found" "$out/stderr" || fail "no gnuplot message"
kept=$(ls -d "$out"/n.png.gnuplot-*)
[ -s "$kept/plot.gp" ] && [ -s "$kept/data0.txt" ] && [ -s "$out/r2.csv" ] \
  || fail "data not kept without gnuplot"
cmp -s "$out/n.png.gp" examples/beam.toml || fail "the kept script replaced n.png.gp"
# A grid reaching below the frequencies whose cone holds a sample of this 1 s
# record (5.4 Hz at coi_factor 2): a note names that frequency; none at the default fmin.
"$podid" cwt "$data" --channel w6 --fmin 1 >/dev/null 2>"$out/low" || fail "cwt --fmin 1 exited $?"
grep -q "note: below 5.40[0-9] Hz no coefficient of this 1 s record is inside the cone" "$out/low" \
  || fail "no low-frequency note: $(cat "$out/low")"
# A cone wider than the record at every frequency of the grid (27 Hz at
# coi_factor 10, above --fmax 20): the note says so instead of suggesting an
# --fmin above --fmax.
"$podid" cwt "$data" --channel w6 --fmin 10 --fmax 20 --coi-factor 10 >/dev/null 2>"$out/wide" \
  || fail "cwt --coi-factor 10 exited $?"
grep -q "note: no coefficient of this 1 s record is inside the cone of influence (coi_factor 10) at any frequency of the grid (up to 20 Hz; the cone holds some from 27.0[0-9] Hz)" "$out/wide" \
  || fail "no whole-grid note: $(cat "$out/wide")"
"$podid" cwt "$data" --channel w6 >/dev/null 2>"$out/default" || fail "cwt exited $?"
[ ! -s "$out/default" ] || fail "unexpected stderr at the default band: $(cat "$out/default")"
# --channel all skips a constant (dead) channel with a note naming it; a
# single constant channel is an error naming the channel and the file.
awk -F, 'NR == 1 { print $0 ",dead"; next } { print $0 ",0" }' "$data" >"$out/dead.csv"
"$podid" cwt "$out/dead.csv" --channel all -o "$out/dead_r.csv" >/dev/null 2>"$out/dead_err" \
  || fail "cwt --channel all with a dead channel exited $?"
grep -q "note: --channel all: 1 constant channel skipped (no ridge): dead$" "$out/dead_err" \
  || fail "no note on the dead channel: $(cat "$out/dead_err")"
grep -q "dead" "$out/dead_r.csv" && fail "the dead channel is in the ridge CSV"
# --channel all with one channel left still names it, and still excludes
# --scalogram and --plot (they were taken, and the columns were bare f_Hz).
cut -d, -f1,2 "$data" >"$out/one.csv"
awk -F, 'NR == 1 { print $0 ",dead"; next } { print $0 ",0" }' "$out/one.csv" >"$out/one_dead.csv"
"$podid" cwt "$out/one_dead.csv" --channel all -o "$out/one_r.csv" >/dev/null 2>&1 \
  || fail "cwt --channel all with one live channel exited $?"
head -1 "$out/one_r.csv" | grep -q "^t,w1_f_Hz,w1_amplitude,w1_inside_coi$" \
  || fail "one live channel's header: $(head -1 "$out/one_r.csv")"
"$podid" cwt "$out/one_dead.csv" --channel all --scalogram "$out/one_sc.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--channel all --scalogram with one live channel not exit 1"
grep -q "(1 channel analysed)" "$out/stderr" || fail "one-channel all message: $(cat "$out/stderr")"
[ ! -e "$out/one_sc.csv" ] || fail "a refused --channel all wrote its scalogram"
"$podid" cwt "$out/dead.csv" --channel dead >/dev/null 2>"$out/dead_err"
[ $? -eq 1 ] || fail "a constant --channel: expected exit 1"
grep -q "^podid: error: dead of $out/dead.csv: .*non-constant" "$out/dead_err" \
  || fail "the error does not name the channel and file: $(cat "$out/dead_err")"
# A record's time x 1e-202 (a 2e-206 s step) put the first mode near
# 3.3e203 Hz, whose squares overflowed the IF statistics (inf or nan; they
# are taken on f / max |f| since). Steps below 1e-15 s are refused now
# (with the energy normalisation such steps gave float scalograms of zeros):
# exit 1, the file and the step named, no output.
awk -F, 'NR == 1 { print; next } { printf "%.12e", $1 * 1e-202; for (c = 2; c <= NF; c++) printf ",%s", $c; print "" }' \
  "$data" >"$out/tiny_step.csv"
"$podid" cwt "$out/tiny_step.csv" --channel w6 --fmin 1e203 --fmax 1.2e204 --penalty 5e-204 \
  -o "$out/tiny_ridge.csv" >"$out/tiny_stdout" 2>"$out/tiny_err"
[ $? -eq 1 ] || fail "cwt of a 2e-206 s step: expected exit 1"
grep -q "^podid: error: w6 of $out/tiny_step.csv: Cwt: step_s: expected a finite value between 1e-15 s and 1e15 s, got 2e-206" \
  "$out/tiny_err" || fail "the 2e-206 s step's error: $(cat "$out/tiny_err")"
[ ! -e "$out/tiny_ridge.csv" ] || fail "a refused step left a ridge file"
# At a step of 2e-15 s (time x 1e-11) the same ridge as at the record's own
# scale, 33-40 Hz x 1e11. (The ridge penalty is in seconds: scaled with the
# time.)
awk -F, 'NR == 1 { print; next } { printf "%.12e", $1 * 1e-11; for (c = 2; c <= NF; c++) printf ",%s", $c; print "" }' \
  "$data" >"$out/small_step.csv"
"$podid" cwt "$out/small_step.csv" --channel w6 --fmin 1e12 --fmax 1.2e13 --penalty 5e-13 \
  >"$out/small_stdout" \
  || fail "cwt of a 2e-15 s step exited $?"
stats=$(grep "mean .* Hz, std" "$out/small_stdout")
echo "$stats" | grep -qi "inf\|nan" && fail "IF statistics overflow: $stats"
mean=$(echo "$stats" | sed -n 's/.*mean \([0-9.e+]*\) Hz.*/\1/p')
std=$(echo "$stats" | sed -n 's/.*std \([0-9.e+-]*\) Hz.*/\1/p')
awk -v m="$mean" -v s="$std" 'BEGIN { exit !(m > 33e11 && m < 40e11 && s > 0 && s < 7e11) }' \
  || fail "IF mean $mean, std $std Hz at the 1e-11 scale"
# A 300 Hz tone analysed on 100-200 Hz: the ridge holds to the grid's top,
# where the phase derivative reads the tone (300 Hz, outside the grid) and a
# note says so; --if scale gives the ridge's grid frequency, 200 Hz. On
# 100-400 Hz both read 300 Hz in the record's middle, each exact for a tone
# (docs/wavelet.md): to 1e-9, which covers the FFT's rounding and the CSV's 13
# digits (measured 6e-12 and 0); and there is no note.
awk 'BEGIN { print "t,x"; for (i = 0; i <= 5000; ++i)
  printf "%.17g,%.17g\n", i / 5000, cos(2 * 3.141592653589793 * 300 * i / 5000) }' >"$out/tone300.csv"
"$podid" cwt "$out/tone300.csv" --channel x --fmin 100 --fmax 200 >"$out/edge" 2>"$out/edge_err" \
  || fail "cwt of a tone above the grid exited $?"
grep -q "mean 299.9[0-9]* Hz" "$out/edge" || fail "phase IF above the grid: $(grep mean "$out/edge")"
grep -q "podid: note: 4865 of 4865 IFs inside the cone lie outside the grid's 100-200 Hz (0 below, 4865 above)" \
  "$out/edge_err" || fail "no outside-the-grid note: $(cat "$out/edge_err")"
grep -q -- "--if scale for IFs on the grid" "$out/edge_err" || fail "note without --if scale"
"$podid" cwt "$out/tone300.csv" --channel x --fmin 100 --fmax 200 --if scale >"$out/edge" \
  2>"$out/edge_err" || fail "cwt --if scale exited $?"
grep -q "IF from the ridge's scale" "$out/edge" || fail "--if scale not reported"
grep -q "mean 200 Hz, std 0 Hz" "$out/edge" || fail "scale IF at the grid's top: $(grep mean "$out/edge")"
[ -s "$out/edge_err" ] && fail "a note with --if scale: $(cat "$out/edge_err")"
for if_from in phase scale; do
  "$podid" cwt "$out/tone300.csv" --channel x --fmin 100 --fmax 400 --if "$if_from" -o "$out/in.csv" \
    >/dev/null 2>"$out/in_err" || fail "cwt --if $if_from in band exited $?"
  [ -s "$out/in_err" ] && fail "a note for a tone inside the grid: $(cat "$out/in_err")"
  awk -F, -v tol=1e-9 \
    'NR > 1 && $1 >= 0.25 && $1 <= 0.75 && ($2 / 300 - 1 > tol || 1 - $2 / 300 > tol) { bad = 1 }
     END { exit bad }' "$out/in.csv" || fail "--if $if_from: IF of the 300 Hz tone off by more than its tolerance"
done
"$podid" cwt "$out/tone300.csv" --channel x --if scale --synchrosqueeze 2>"$out/stderr"
[ $? -eq 1 ] || fail "--if with --synchrosqueeze not exit 1"
"$podid" cwt "$out/tone300.csv" --channel x --if bogus 2>"$out/stderr"
[ $? -eq 1 ] || fail "--if bogus not exit 1"
grep -q 'expected one of phase, scale, got "bogus"' "$out/stderr" || fail "--if bogus message"
# --max-memory bounds the process: the ridge search over the whole transform
# (a cost and a back-pointer a cell) counts. 2000 samples x 9500 frequencies
# with --ridges 2 passed a 300 MB limit and peaked at 503 MB; W and the search
# need 2000 x 9500 x 28 bytes = 507 MB. Peak RSS of the child, in MiB; the
# allowance is the refused run's own peak (the process without a transform).
awk 'BEGIN { print "t,a"; for (i = 0; i < 2000; i++) { t = i / 1000
  printf "%.6f,%.12f\n", t, sin(2 * 3.141592653589793 * 50 * t) } }' >"$out/mem.csv"
peak_mb() {
  python3 -c 'import resource, subprocess, sys
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(r.returncode, int(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))' "$@"
}
read -r rc base <<<"$(peak_mb "$podid" cwt "$out/mem.csv" --channel a --fmin 10 --fmax 200 \
  --bins 9500 --ridges 2 --max-memory 300)"
[ "$rc" -eq 1 ] || fail "--bins 9500 --ridges 2 in 300 MB not exit 1 (exit $rc)"
read -r rc peak <<<"$(peak_mb "$podid" cwt "$out/mem.csv" --channel a --fmin 10 --fmax 200 \
  --bins 9500 --ridges 2 --max-memory 520)"
[ "$rc" -eq 0 ] || fail "--bins 9500 --ridges 2 in 520 MB exited $rc"
# Not under AddressSanitizer: its shadow memory and quarantine are not the
# process's own (700 MB peak against 520 + 109 there).
if ! ldd "$podid" 2>/dev/null | grep -q libasan; then
  [ "$peak" -le $((520 + base)) ] || fail "--max-memory 520: peak $peak MB (process alone $base MB)"
fi

echo "cli.cwt: ok"
