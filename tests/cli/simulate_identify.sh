#!/usr/bin/env bash
# End-to-end test of `podid modes`, `simulate`, `identify` and `landscape`.
# Usage: bash tests/cli/simulate_identify.sh PODID (from the repo root).
set -u
podid="$1"
. tests/support/cli.sh
cli_scratch

# modes: the reference frequencies.
"$podid" modes examples/beam.toml >"$out/modes" || fail "modes exited $?"
grep -Eq "^ +1 +32\.97" "$out/modes" || fail "mode 1 not 32.97 Hz"
grep -Eq "^ +2 +206\.6[78]" "$out/modes" || fail "mode 2 not 206.68 Hz"

# simulate: the shared data's format, 501 rows + header, and the first row
# equal to the independent data's (the static deflection) to 9 digits.
"$podid" simulate examples/beam.toml -o "$out/sim.csv" >"$out/stdout" || fail "simulate exited $?"
grep -q "completed, 500/500 steps" "$out/stdout" || fail "simulate summary"
[ "$(head -1 "$out/sim.csv")" = "t,w1,w2,w3,w4,w5,w6" ] || fail "header"
[ "$(wc -l <"$out/sim.csv")" -eq 502 ] || fail "rows"
tip=$(sed -n 2p "$out/sim.csv" | cut -d, -f7)
awk -v x="$tip" 'BEGIN { exit !(x > 1.2009e-3 && x < 1.2011e-3) }' || fail "tip deflection $tip"
# --set overrides and the integrator choice.
"$podid" simulate examples/beam.toml --set time.duration=0.01 --set integrator.type=newmark \
  -o "$out/short.csv" >/dev/null || fail "simulate --set exited $?"
[ "$(wc -l <"$out/short.csv")" -eq 52 ] || fail "short rows"

# Bad input: exit 1, one line naming the key, no output file.
"$podid" simulate examples/beam.toml --set beam.length=-1 -o "$out/bad.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "negative length not exit 1"
grep -q "beam.length" "$out/stderr" || fail "message lacks the key"
[ "$(wc -l <"$out/stderr")" -eq 1 ] || fail "error is not one line"
[ -e "$out/bad.csv" ] && fail "output written on error"
# A diverging simulation: exit 2, the partial history written, the time named.
"$podid" simulate examples/beam.toml --set nonlinearity.1.type=friction --set nonlinearity.1.node=6 \
  --set nonlinearity.1.mu=1 --set nonlinearity.1.normal_force=5 \
  --set nonlinearity.1.velocity_scale=1e-9 -o "$out/fail.csv" >"$out/stdout" 2>"$out/stderr"
[ $? -eq 2 ] || fail "diverging simulation not exit 2"
grep -q "Newton failed at t = " "$out/stderr" || fail "failure message"
[ -s "$out/fail.csv" ] || fail "partial history not written"

# identify: knl within 0.5 % of 50 from 40, JSON with the documented keys.
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --start knl=40 \
  --json "$out/id.json" >"$out/stdout" || fail "identify exited $?"
python3 - "$out/id.json" <<'PY' || fail "identify JSON"
import json, sys
j = json.load(open(sys.argv[1]))
for key in ("parameters", "objective", "evaluations", "termination", "history"):
    assert key in j, key
assert abs(j["parameters"]["knl"] / 50 - 1) < 0.005, j["parameters"]
assert j["termination"] == "converged", j["termination"]
assert len(j["history"]) == j["evaluations"]
assert "ridges" not in j  # no wavelet term
PY
# Errors: unknown parameter, start out of bounds, wavelet objective on a short record.
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --start k3=40 2>"$out/stderr"
[ $? -eq 1 ] || fail "unknown parameter not exit 1"
grep -q "expected a parameter name (knl)" "$out/stderr" || fail "unknown parameter message"
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --start knl=400 2>"$out/stderr"
[ $? -eq 1 ] || fail "start out of bounds not exit 1"
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --objective wavelet 2>"$out/stderr"
[ $? -eq 1 ] || fail "short record not exit 1"
grep -q "lowest frequency" "$out/stderr" || fail "short record message"

# landscape: metrics table and a complete CSV.
"$podid" landscape examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --param knl \
  --range 0:100:21 --objective full,time-free -o "$out/land.csv" --json "$out/land.json" \
  >"$out/stdout" || fail "landscape exited $?"
grep -Eq "^full +[0-9]+ +50 " "$out/stdout" || fail "full minimiser not 50"
[ "$(head -1 "$out/land.csv")" = "knl,full,time-free" ] || fail "landscape header"
[ "$(wc -l <"$out/land.csv")" -eq 22 ] || fail "landscape rows"
"$podid" landscape examples/beam.toml --measured tests/data/measured_knl50_T0.1.csv --param knl \
  --range 0:100 2>"$out/stderr"
[ $? -eq 1 ] || fail "bad range not exit 1"
grep -q "LOWER:UPPER:POINTS" "$out/stderr" || fail "range message"
# The wavelet term with MATLAB's default Morse wavelet (gamma 3, beta 20):
# knl within 0.5 % of 50 from 25 on the 1 s record, and the landscape's
# wavelet minimum at 50 on a 1-wide grid; a bad family, or beta / gamma > 100,
# exits 1 naming the option and writes nothing.
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T1.0.csv --objective wavelet \
  --start knl=25 --wavelet morse --json "$out/morse.json" >"$out/stdout" 2>/dev/null ||
  fail "identify --wavelet morse exited $?"
knl=$(sed -n 's/.* knl = \([0-9.]*\) .*/\1/p' "$out/stdout")
awk -v k="$knl" 'BEGIN { exit !(k > 49.75 && k < 50.25) }' || fail "Morse knl '$knl'"
# The JSON names the wavelet term's settings as the objective resolved them.
python3 - "$out/morse.json" <<'PY' || fail "identify --wavelet morse JSON"
import json, sys
r = json.load(open(sys.argv[1]))["ridges"]
assert len(r) == 1 and r[0]["mode"] == 1, r
assert r[0]["wavelet"] == "Morse gamma 3 beta 20" and r[0]["penalty_s"] == 0.05, r
assert (r[0]["min_frequency_Hz"], r[0]["max_frequency_Hz"]) == (10, 120), r
assert r[0]["normalisation"] == "amplitude" and r[0]["scale_convention"] == "ridge", r
assert r[0]["samples_compared"] > 0, r
PY
"$podid" landscape examples/beam.toml --measured tests/data/measured_knl50_T1.0.csv --param knl \
  --range 40:60:21 --objective wavelet --wavelet morse -o "$out/morse.csv" --json "$out/land.json" \
  >/dev/null 2>&1 || fail "landscape --wavelet morse exited $?"
best=$(tail -n +2 "$out/morse.csv" | sort -t, -k2 -g | head -1 | cut -d, -f1)
[ "$best" = "50" ] || fail "Morse landscape minimum at '$best'"
python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))["ridges"]; assert r[0]["wavelet"] == "Morse gamma 3 beta 20", r' \
  "$out/land.json" || fail "landscape --json ridges"
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T1.0.csv --objective wavelet \
  --wavelet mexhat --json "$out/bad.json" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--wavelet mexhat not exit 1"
grep -q -- "--wavelet: expected one of morlet, morse" "$out/stderr" || fail "--wavelet message: $(cat "$out/stderr")"
"$podid" identify examples/beam.toml --measured tests/data/measured_knl50_T1.0.csv --objective wavelet \
  --wavelet morse --gamma 1 --beta 200 --json "$out/bad.json" 2>"$out/stderr"
[ $? -eq 1 ] || fail "beta / gamma 200 not exit 1"
grep -q -- "--beta: expected at most 100 x --gamma (1), got 200" "$out/stderr" || fail "--beta message: $(cat "$out/stderr")"
[ -e "$out/bad.json" ] && fail "output written on error"
echo "simulate_identify: all checks passed"
