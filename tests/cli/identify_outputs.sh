#!/usr/bin/env bash
# What identify and landscape write, and the notes they give, at the edges:
# a run where every evaluation fails writes nothing; --json may go into the
# --plot-dir the run creates; an interval that crosses a bound says so; a
# landscape beyond the bounds and a dead sensor get a note.
# Usage: bash tests/cli/identify_outputs.sh PODID (from the repo root).
set -u
podid="$1"
. tests/support/cli.sh
cli_scratch
short=tests/data/measured_knl50_T0.1.csv
# A friction element with a tiny velocity scale: Newton fails in every
# simulation (as in simulate_identify.sh), so every evaluation fails.
diverge=(--set nonlinearity.1.type=friction --set nonlinearity.1.node=6 --set nonlinearity.1.mu=1
  --set nonlinearity.1.normal_force=5 --set nonlinearity.1.velocity_scale=1e-9)

# 1. No usable point: exit 2 with the first failure, and neither the JSON nor
#    the plot folder (earlier files untouched).
echo "earlier" >"$out/earlier.json"
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 --max-evaluations 5 \
  "${diverge[@]}" --json "$out/earlier.json" --plot-dir "$out/plots" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 2 ] || fail "every evaluation failing: exit $rc, expected 2: $(cat "$out/stderr")"
grep -q "Newton failed" "$out/stderr" || fail "the first failure not quoted: $(cat "$out/stderr")"
grep -q "no file written" "$out/stderr" || fail "'no file written' missing: $(cat "$out/stderr")"
[ "$(cat "$out/earlier.json")" = "earlier" ] || fail "the earlier JSON was replaced"
[ -e "$out/plots" ] && fail "the plot folder was created on failure"

# 2. --json inside the --plot-dir this run creates: both written.
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 --plot-dir "$out/new" \
  --json "$out/new/result.json" >"$out/stdout" 2>"$out/stderr" ||
  fail "--json in a new --plot-dir exited $?: $(cat "$out/stderr")"
[ -s "$out/new/result.json" ] || fail "result.json not written"
[ -s "$out/new/signals.csv" ] || fail "signals.csv not written"
# ... but not under one of the plots' own names, and not in a folder below it.
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 --plot-dir "$out/new2" \
  --json "$out/new2/signals.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--json on signals.csv of a new --plot-dir not exit 1"
grep -q "^podid: error: --json: expected a file other than --plot-dir's signals.csv" "$out/stderr" ||
  fail "signals.csv clash message: $(cat "$out/stderr")"
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 --plot-dir "$out/new3" \
  --json "$out/new3/sub/r.json" 2>"$out/stderr"
[ $? -eq 1 ] || fail "--json below a new --plot-dir not exit 1"
grep -q "^podid: error: --json: " "$out/stderr" || fail "sub-folder message: $(cat "$out/stderr")"
[ -e "$out/new2" ] || [ -e "$out/new3" ] && fail "a refused run created its --plot-dir"

# 3. An interval that crosses a bound: the optimum of the short record is
#    knl = 50.11 (interval about 50.06..50.16); with the upper bound at 50.13
#    the interval goes beyond it, and the line and the JSON say so.
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 \
  --set identify.parameter.0.upper=50.13 --json "$out/bound.json" >"$out/stdout" 2>"$out/stderr" ||
  fail "identify with upper 50.13 exited $?: $(cat "$out/stderr")"
grep -q "above the upper bound 50.13)" "$out/stdout" || fail "bound note missing: $(cat "$out/stdout")"
python3 - "$out/bound.json" <<'PY' || fail "bound_note in the JSON"
import json, sys
u = json.load(open(sys.argv[1]))["uncertainty"]["parameters"]["knl"]
assert u["upper"] > 50.13 and u["bound_note"] == "above the upper bound 50.13", u
PY
# Within the bounds: no note.
"$podid" identify examples/beam.toml --measured "$short" --start knl=40 >"$out/stdout" 2>&1 ||
  fail "identify exited $?"
grep -q "bound" "$out/stdout" && fail "a bound note without reason: $(cat "$out/stdout")"

# 4. A landscape beyond the bounds (knl in 0..200): evaluated, with a note.
"$podid" landscape examples/beam.toml --measured "$short" --param knl --range 150:250:3 \
  --objective time-free -o "$out/land.csv" >"$out/stdout" 2>"$out/stderr" ||
  fail "landscape beyond the bounds exited $?: $(cat "$out/stderr")"
grep -q "^podid: note: --range 150..250 goes beyond knl's bounds 0..200 (\[\[identify.parameter\]\]): identify does not search there$" \
  "$out/stderr" || fail "landscape bound note: $(cat "$out/stderr")"
[ "$(wc -l <"$out/land.csv")" -eq 4 ] || fail "landscape rows"

# 5. A dead sensor: w1 zero throughout; pod and identify name it.
awk -F, 'BEGIN { OFS = "," } NR > 1 { $2 = 0 } { print }' "$short" >"$out/dead.csv"
"$podid" pod "$out/dead.csv" >/dev/null 2>"$out/stderr" || fail "pod on a dead channel exited $?"
grep -q "^podid: note: $out/dead.csv: channel w1 is zero in all 501 samples: a dead or disconnected sensor?$" \
  "$out/stderr" || fail "pod's dead-sensor note: $(cat "$out/stderr")"
"$podid" identify examples/beam.toml --measured "$out/dead.csv" --start knl=40 >/dev/null 2>"$out/stderr" ||
  fail "identify on a dead channel exited $?"
grep -q "channel w1 is zero in all 501 samples" "$out/stderr" || fail "identify's note: $(cat "$out/stderr")"
exit 0
