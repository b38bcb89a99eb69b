#!/usr/bin/env bash
# docs/real-data.md's F-16 example, examples/f16/run.py, against an
# independent parse of the file (scipy.io.loadmat): the live channels, their
# POD (NumPy's SVD) and the ridge IF of the sine sweep (the force's phase
# derivative, scipy.signal.hilbert). Exit 77 (skipped) without
# ../shared/realdata (or $PODID_REALDATA).
# Usage: bash tests/cli/f16_example.sh PODID (from the repo root).
set -eu
podid=$1
. tests/support/cli.sh
cli_realdata testlab/F16_Data.mat "the F-16 example"
file="$real/testlab/F16_Data.mat"
cli_python "to check the example (Debian's python3-scipy)" numpy scipy.io scipy.signal
cli_scratch
"$py" examples/f16/run.py "$podid" "$file" "$out"
"$py" tests/f16_example_check.py "$file" "$out/summary.json"
