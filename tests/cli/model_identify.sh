#!/usr/bin/env bash
# End-to-end identification on the new model sources: simulate with one value,
# identify from another start, for (1) the reference beam measured in
# acceleration, (2) a pinned-pinned beam with a point mass
# (examples/pinned_mass.toml), (3) two beams given only as matrices joined by
# a cubic spring (examples/two_beams/), plus `modes` and errors of these cases.
# Usage: bash tests/cli/model_identify.sh PODID (from the repo root).
set -u
podid="$1"
. tests/support/cli.sh
cli_scratch
py=python3  # any python3 with json

# Checks that the JSON's parameter $2 is within $3 (relative) of $4.
check() {
  "$py" - "$1" "$2" "$3" "$4" <<'PY' || fail "identify $1: $2"
import json, sys
j = json.load(open(sys.argv[1]))
value, tol, truth = j["parameters"][sys.argv[2]], float(sys.argv[3]), float(sys.argv[4])
assert abs(value / truth - 1) < tol, (sys.argv[2], value, truth)
assert j["termination"] == "converged", j["termination"]
PY
}

# (1) The reference beam measured in acceleration: knl = 50 from 40.
"$podid" simulate examples/beam.toml --set sensors.quantity=acceleration --no-noise \
  -o "$out/acc.csv" >/dev/null || fail "simulate acceleration exited $?"
[ "$(head -1 "$out/acc.csv")" = "t,w1,w2,w3,w4,w5,w6" ] || fail "acceleration header"
"$podid" identify examples/beam.toml --set sensors.quantity=acceleration --measured "$out/acc.csv" \
  --start knl=40 --json "$out/acc.json" >/dev/null || fail "identify acceleration exited $?"
check "$out/acc.json" knl 0.005 50

# (2) Pinned-pinned beam with a point mass, measured in acceleration: the
# data with knl = 60 and mass = 0.5 kg; identify both from 40 and 0.4 kg.
"$podid" modes examples/pinned_mass.toml --count 2 >"$out/modes" || fail "modes pinned exited $?"
grep -q "16 dofs" "$out/modes" || fail "pinned-pinned beam of 8 elements has 16 dofs: $(head -1 "$out/modes")"
"$podid" simulate examples/pinned_mass.toml --set nonlinearity.0.k3=6e10 --no-noise \
  -o "$out/pinned.csv" >/dev/null || fail "simulate pinned exited $?"
[ "$(head -1 "$out/pinned.csv")" = "t,a2,a3,a4,a5,a6" ] || fail "pinned header"
"$podid" identify examples/pinned_mass.toml --measured "$out/pinned.csv" \
  --json "$out/pinned.json" >/dev/null || fail "identify pinned exited $?"
check "$out/pinned.json" knl 0.01 60
"$podid" identify examples/pinned_mass.toml --measured "$out/pinned.csv" \
  --set identify.parameter.1.key=mass.0.mass --set identify.parameter.1.name=m \
  --set identify.parameter.1.scale=1 --set identify.parameter.1.start=0.4 \
  --set identify.parameter.1.lower=0.05 --set identify.parameter.1.upper=2 \
  --json "$out/pinned2.json" >/dev/null || fail "identify pinned (knl, mass) exited $?"
check "$out/pinned2.json" knl 0.02 60
check "$out/pinned2.json" m 0.02 0.5

# (3) Two beams given as matrices, joined by a cubic spring: knl = 70 from 40.
"$podid" simulate examples/two_beams/two_beams.toml --set nonlinearity.0.k3=7e9 --no-noise \
  -o "$out/two.csv" >/dev/null || fail "simulate two beams exited $?"
[ "$(head -1 "$out/two.csv")" = "t,a4,a5,a6,b4,b5,b6" ] || fail "two beams header"
"$podid" identify examples/two_beams/two_beams.toml --measured "$out/two.csv" \
  --json "$out/two.json" >/dev/null || fail "identify two beams exited $?"
check "$out/two.json" knl 0.005 70

# The Duffing example runs.
"$podid" simulate examples/duffing/duffing.toml -o "$out/duffing.csv" >/dev/null || fail "duffing exited $?"
[ "$(head -1 "$out/duffing.csv")" = "t,x" ] || fail "duffing header"
# Its one mode, analytic: k = (2 pi 5 Hz)^2, m = 1, c = 0.4 give 5 Hz and
# zeta = c / (2 sqrt(k m)) = 0.4 / (20 pi) = 0.006366 (printed to 4 and 6 digits).
"$podid" modes examples/duffing/duffing.toml >"$out/modes_duffing" || fail "modes duffing exited $?"
grep -Eq "^ +1 +5\.0000 +0\.006366$" "$out/modes_duffing" || fail "duffing modes: $(cat "$out/modes_duffing")"

# `modes` reads no excitation: the Silverbox case's force is a channel of a
# data file that only the command line names (run.py), and its linear model
# (K = 0; the stiffness is the polynomial element's k1) has one 0 Hz mode.
"$podid" modes examples/silverbox/silverbox.toml >"$out/modes_sb" 2>"$out/stderr" ||
  fail "modes silverbox exited $?: $(cat "$out/stderr")"
grep -q "imported matrices, 1 dofs" "$out/modes_sb" || fail "silverbox modes: $(cat "$out/modes_sb")"
grep -Eq "^ +1 +0\.0000 " "$out/modes_sb" || fail "silverbox mode: $(cat "$out/modes_sb")"

# Errors: exit 1, one line naming the key.
"$podid" simulate examples/two_beams/two_beams.toml --set initial.dof=25 -o "$out/bad.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "dof 25 not exit 1"
grep -q "initial.dof: expected an integer in \[1, 24\], got 25" "$out/stderr" || fail "dof message: $(cat "$out/stderr")"
"$podid" simulate examples/pinned_mass.toml --set beam.left=hinged -o "$out/bad.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "hinged not exit 1"
grep -q "beam.left: expected one of" "$out/stderr" || fail "left message: $(cat "$out/stderr")"
echo "model_identify: all checks passed"
