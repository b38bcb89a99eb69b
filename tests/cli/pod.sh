#!/usr/bin/env bash
# End-to-end test of `podid pod`. Usage: bash tests/cli/pod.sh PODID (from the repo root).
set -u
podid="$1"
data=tests/data/measured_knl50_T0.1.csv
. tests/support/cli.sh
cli_scratch

# Full decomposition: table, JSON and time modes.
"$podid" pod "$data" --json "$out/pod.json" -o "$out/v.csv" >"$out/stdout" \
  || fail "pod exited $?"
grep -q "6 channels x 501 samples, method direct, numerical rank 6" "$out/stdout" \
  || fail "summary line"
[ "$(grep -c '^ *[0-9]  ' "$out/stdout")" -eq 6 ] || fail "6 mode rows"
# The paper (sec. 4.3.3): the first POM holds more than 60 % of the energy.
energy=$(awk '$1 == "1" { print $4 }' "$out/stdout")
awk -v e="$energy" 'BEGIN { exit !(e > 60) }' || fail "first POM energy $energy %"
[ "$(head -1 "$out/v.csv")" = "t,v1,v2,v3,v4,v5,v6" ] || fail "V header"
[ "$(wc -l <"$out/v.csv")" -eq 502 ] || fail "V rows"
/usr/bin/python3 - "$out/pod.json" <<'PY' || fail "JSON content"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["method"] == "direct" and j["sensors"] == 6 and j["samples"] == 501
assert len(j["poms"]) == 6 and all(len(p) == 6 for p in j["poms"])
assert abs(sum(u * u for u in j["poms"][0]) - 1) < 1e-12
assert j["energy_fraction"][0] > 0.6 and abs(j["cumulative_energy"][-1] - 1) < 1e-12
PY

# Truncation and method choice: svd keeps the two modes above 99.9 % of the energy.
"$podid" pod "$data" --method svd --energy 0.999 >"$out/stdout" || fail "--energy exited $?"
grep -q "method svd" "$out/stdout" || fail "svd not used"
[ "$(grep -c '^ *[0-9]  ' "$out/stdout")" -eq 2 ] || fail "--energy 0.999 should keep 2 modes"
"$podid" pod "$data" --method snapshot --modes 1 --no-mean >"$out/stdout" || fail "--modes exited $?"
[ "$(grep -c '^ *[0-9]  ' "$out/stdout")" -eq 1 ] || fail "--modes 1"

# Bad input: exit 1, one-line message with what was expected; no output file.
"$podid" pod "$data" --modes 7 -o "$out/bad.csv" 2>"$out/stderr" && fail "--modes 7 accepted"
grep -q "expected <= min(channels, samples) = 6" "$out/stderr" || fail "--modes message"
[ -e "$out/bad.csv" ] && fail "output written on error"
"$podid" pod "$data" --method qr 2>"$out/stderr"
[ $? -eq 1 ] || fail "bad method exit code"
grep -q "expected one of auto, svd, direct, snapshot" "$out/stderr" || fail "method message"
"$podid" pod "$data" --energy 1.5 2>"$out/stderr"
[ $? -eq 1 ] || fail "bad energy exit code"
grep -q -- '--energy: expected a number in (0, 1], got "1.5"' "$out/stderr" || fail "energy message"
# A threshold above every sigma keeps nothing: refused, and no file written
# (it wrote a CSV of times only, which podid cannot read back).
"$podid" pod "$data" --sigma-threshold 1 -o "$out/none.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "sigma-threshold above every sigma: exit code"
grep -q -- "--sigma-threshold: expected a threshold below the largest singular value" "$out/stderr" \
  || fail "sigma-threshold message: $(cat "$out/stderr")"
[ ! -e "$out/none.csv" ] || fail "sigma-threshold above every sigma wrote a file"
"$podid" pod "$out/missing.csv" 2>"$out/stderr"
[ $? -eq 1 ] || fail "missing file exit code"
echo "pod CLI: ok"
