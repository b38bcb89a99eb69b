#!/usr/bin/env bash
# Hostile and careless input to the podid executable (issue 10 items 5-9):
# values the schema accepts never abort, an evaluation that throws is a failed
# point (never SIGABRT), a landscape where every point fails exits 2 without
# files, counts and sizes are bounded before anything is allocated, degenerate
# data say so, and a file's bytes reach stderr only as a short escaped excerpt.
# Usage: bash tests/cli/hostile_inputs.sh PODID (from the repo root).
set -u
podid="$1"
case_file=examples/beam.toml
measured=tests/data/measured_knl50_T1.0.csv
. tests/support/cli.sh
cli_scratch
# expect CODE NEEDLE -- ARGS...: podid exits CODE and stderr contains NEEDLE.
expect() {
  local code="$1" needle="$2"
  shift 3
  "$podid" "$@" >"$out/stdout" 2>"$out/stderr"
  local rc=$?
  [ $rc -eq "$code" ] || fail "podid $*: exit $rc, expected $code ($(tail -c 300 "$out/stderr"))"
  grep -qF -- "$needle" "$out/stderr" || fail "podid $*: stderr lacks '$needle': $(tail -c 300 "$out/stderr")"
}

# Item 6: schema-valid values used to trip PODID_CHECKs (exit 134).
expect 1 "beam.youngs_modulus: expected a modulus > 0 Pa between 2.3e-308" -- \
  modes "$case_file" --set beam.youngs_modulus=1e-320
expect 1 "expected a second moment of area > 0 m^4" -- modes "$case_file" --set beam.area=1e300
expect 1 "expected a frequency scale" -- modes "$case_file" --set beam.length=1e-100

# Item 7: a zero response (no static force) made the CWT throw through NLopt's
# callback and an OpenMP region (SIGABRT).
expect 2 "identify: every evaluation failed; e.g. at the start: " -- \
  identify "$case_file" -m "$measured" --objective wavelet --set initial.static_tip_force=0 \
  --multistart 2 --max-evaluations 4

# Item 9: every point failing is not "completed"; nothing is written.
expect 2 "landscape: no point succeeded, 3 points (3 failed)" -- \
  landscape "$case_file" -m "$measured" --param knl --range 0:100:3 \
  --set initial.static_tip_force=0 -o "$out/l.csv"
[ ! -e "$out/l.csv" ] || fail "a landscape with no successful point wrote its CSV"
expect 1 "bounds whose difference UPPER - LOWER is finite" -- \
  landscape "$case_file" -m "$measured" --param knl --range -1.7e308:1.7e308:3
expect 1 "--range: expected at most 1000000 POINTS" -- \
  landscape "$case_file" -m "$measured" --param knl --range 0:1:10000000
printf 't,a,b\n0,1e-304,2e-304\n0.001,-1e-304,1e-304\n0.002,3e-304,-2e-304\n' >"$out/tiny.csv"
expect 2 "degenerate data: numerical rank 0" -- pod "$out/tiny.csv" --json "$out/tiny.json"
[ ! -e "$out/tiny.json" ] || fail "pod of degenerate data wrote its JSON"

# A FIFO or a folder as a data, force or matrix file is refused before it is
# opened: opening a FIFO without a writer blocked podid for ever.
mkfifo "$out/fifo.csv" "$out/fifo.uff" "$out/fifo.mat" "$out/fifo.mtx"
for f in fifo.csv fifo.uff fifo.mat; do
  timeout 60 "$podid" pod "$out/$f" >"$out/stdout" 2>"$out/stderr"
  rc=$?
  [ $rc -eq 1 ] || fail "pod $f: exit $rc, expected 1"
  grep -q "$f: expected a readable .*, got a FIFO (named pipe)" "$out/stderr" || fail "pod $f: $(cat "$out/stderr")"
done
mkdir -p "$out/folder.csv"
expect 1 "folder.csv: expected a readable CSV file, got a directory" -- pod "$out/folder.csv"
timeout 60 "$podid" simulate "$case_file" --set force.0.type=file --set "force.0.file=\"$out/fifo.csv\"" \
  --set force.0.column=N --set force.0.node=6 -o "$out/never.csv" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] && grep -q "got a FIFO" "$out/stderr" || fail "FIFO force file: exit $rc: $(cat "$out/stderr")"
printf '[model]\ntype = "matrices"\nmass = "fifo.mtx"\nstiffness = "fifo.mtx"\n[time]\nduration = 0.1\nstep = 0.01\n' \
  >"$out/fifo_model.toml"
timeout 60 "$podid" modes "$out/fifo_model.toml" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] && grep -q "fifo.mtx: expected a readable Matrix Market file, got a FIFO" "$out/stderr" \
  || fail "FIFO matrix file: exit $rc: $(cat "$out/stderr")"

# A record starting at t = 1e9 s is written with enough digits to read back
# (at 13 digits its 501 stamps were all 1.000000000000e+09).
"$podid" simulate "$case_file" --set time.start=1e9 -o "$out/late.csv" >/dev/null 2>"$out/stderr" \
  || fail "simulate from t = 1e9 s: $(cat "$out/stderr")"
"$podid" pod "$out/late.csv" --json "$out/late.json" >/dev/null 2>"$out/stderr" \
  || fail "a record from t = 1e9 s does not read back: $(cat "$out/stderr")"
grep -q '"samples": 501' "$out/late.json" || fail "late.json: $(head -c 300 "$out/late.json")"

# Item 8: /dev/zero as a case file grew to GBs; now it fails at 1 MiB + 1.
start=$(date +%s)
expect 1 "expected a case file of at most 1048576 bytes (1 MiB)" -- modes /dev/zero
[ $(( $(date +%s) - start )) -lt 10 ] || fail "modes /dev/zero took more than 10 s"
python3 -c "print('[beam]\n' + '.'.join(['a'] * 40000) + ' = 1')" >"$out/deep.toml"
expect 1 "deep.toml:2: expected TOML nested at most 32 levels deep" -- modes "$out/deep.toml"

# Item 5: a force file that is not CSV (no comma in its first line) shows none of its content.
printf 'root:$6$saltsalt$SECRETHASH:19000:0:99999:7:::\ndaemon:*:19000:0:99999:7:::\n' \
  >"$out/shadow"
expect 1 'got a first line of 46 bytes without a comma' -- simulate "$case_file" --set force.type=file \
  --set force.file="$out/shadow" --set force.column=x -o "$out/s.csv"
grep -q "root:\|saltsalt\|SECRETHASH\|daemon" "$out/stderr" && fail "the force file's content reached stderr"
printf 't,\033[2Jw1\n0,1\n1,2\n' >"$out/esc.csv"
expect 1 'expected column names without control characters, got "\x1b[2Jw1"' -- pod "$out/esc.csv"
if grep -q $'\033' "$out/stderr"; then fail "an escape character reached stderr"; fi

# Item 8: std::bad_alloc never reaches the user bare. A 400 MB address space
# cannot hold 2e7 samples x 6 channels (1 GB); skipped where podid cannot even
# start in it (sanitizer builds reserve terabytes of address space).
if (ulimit -v 400000; "$podid" --version) >/dev/null 2>&1; then
  (ulimit -v 400000; "$podid" simulate "$case_file" --set time.step=5e-9 -o "$out/big.csv") \
    >"$out/stdout" 2>"$out/stderr"
  rc=$?
  [ $rc -eq 1 ] || fail "out of memory: exit $rc, expected 1"
  grep -q "^podid: error: out of memory: " "$out/stderr" || fail "out of memory: $(cat "$out/stderr")"
fi

# Option names, not the library's fields: a band above the measured data's
# Nyquist frequency was "Cwt: frequencies.max_frequency_Hz: ..."; a repeated
# --mode-band silently kept the later one; cwt's names were "padding:",
# "ridge method:", "frequency estimator:".
expect 1 "--fmax: expected at most the measured data's Nyquist frequency, 2500 Hz (step 0.0002 s), got 3000 Hz" -- \
  identify "$case_file" -m "$measured" --objective wavelet --fmax 3000
expect 1 "--fmax: expected at most the measured data's Nyquist" -- \
  landscape "$case_file" -m "$measured" --param knl --range 40:60:5 --objective wavelet --fmax 3000
expect 1 "--mode-band: expected HIGH at most the measured data's Nyquist frequency, 2500 Hz, got 2=10:3000" -- \
  identify "$case_file" -m "$measured" --objective wavelet --modes 2 --mode-band 2=10:3000
expect 1 '--mode-band: expected each mode K at most once, got mode 2 twice ("2=20:100")' -- \
  identify "$case_file" -m "$measured" --objective wavelet --modes 2 --mode-band 2=10:100 \
  --mode-band 2=20:100
# Without a wavelet term --fmax is not read: refused as such (it was
# silently ignored; tests/cli/wavelet_term_options.sh has the others).
expect 1 "--fmax: expected an objective with the wavelet (IF) term" -- \
  identify "$case_file" -m "$measured" --objective full --fmax 3000 --max-evaluations 1
expect 1 '--padding: expected one of reflect, zero, periodic, got "foo"' -- \
  cwt "$measured" --channel w1 --padding foo
expect 1 '--ridge: expected one of max, penalised, got "foo"' -- cwt "$measured" --channel w1 --ridge foo
expect 1 '--if: expected one of phase, scale, got "foo"' -- cwt "$measured" --channel w1 --if foo
expect 1 '--samples 100: --padding: expected one of reflect, zero, periodic, got "foo"' -- \
  plan --samples 100 --fs 1000 --padding foo

echo "hostile inputs: ok"
