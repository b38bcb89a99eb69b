#!/usr/bin/env bash
# docs/real-data.md's Silverbox example, examples/silverbox/run.py, on the real
# file: the Duffing model fitted on the multisine part must simulate the
# growing-amplitude part it never saw to <= 0.5 mV RMS (issue 12 item 8), the
# linear fit must not (it gets ~14 mV), and every parameter's 95 % interval
# must hold its value. The RMS uses V2 as scipy.io.loadmat reads it, not podid.
# Exit 77 (skipped) without ../shared/realdata (or $PODID_REALDATA).
# Usage: bash tests/cli/silverbox_example.sh PODID (from the repo root).
set -eu
podid=$1
. tests/support/cli.sh
cli_realdata silverbox/SNLS80mV.mat "the Silverbox example"
file="$real/silverbox/SNLS80mV.mat"
cli_python "to run the example (Debian's python3-scipy)" numpy scipy.io
cli_scratch
"$py" examples/silverbox/run.py "$podid" "$file" "$out"
"$py" - "$out/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
duffing, linear = s["duffing"], s["linear"]
# The issue's target for the 5-parameter Duffing model.
kTargetRms_mV = 0.5
assert duffing["validation_rms_mV"] <= kTargetRms_mV, duffing
# A linear model cannot follow the growing amplitude: the issue's best linear
# model gets 14 mV; 10 mV separates the two by a factor 20.
kLinearAtLeast_mV = 10.0
assert linear["validation_rms_mV"] >= kLinearAtLeast_mV, linear
for fit in (duffing, linear):
    assert fit["termination"] == "converged", fit
    assert set(fit["intervals_95"]) == set(fit["parameters"]), fit
    for name, (lower, upper) in fit["intervals_95"].items():
        assert lower < fit["parameters"][name] < upper, (name, fit)
# The cubic stiffness is there: its interval excludes 0.
assert duffing["intervals_95"]["k3"][0] > 0, duffing
print("silverbox example: Duffing %.4f mV, linear %.3f mV" %
      (duffing["validation_rms_mV"], linear["validation_rms_mV"]))
PY
