#!/usr/bin/env bash
# docs/real-data.md's F-16 example, examples/f16/run.py, against an
# independent parse of the file (scipy.io.loadmat): the live channels, their
# POD (NumPy's SVD) and the ridge IF of the sine sweep (the force's phase
# derivative, scipy.signal.hilbert). Exit 77 (skipped) without
# ../shared/realdata (or $PODID_REALDATA).
# Usage: bash tests/cli/f16_example.sh PODID (from the repo root).
set -eu
podid=$1
real="${PODID_REALDATA:-../shared/realdata}"
file="$real/testlab/F16_Data.mat"
if [ ! -f "$file" ]; then
  echo "SKIP: $file is absent (the shared real data): the F-16 example is not run"
  exit 77
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3
if ! "$py" -c "import numpy, scipy.io, scipy.signal" 2>/dev/null; then
  echo "SKIP: no Python with NumPy and SciPy (Debian's python3-scipy) to check the example"
  exit 77
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$py" examples/f16/run.py "$podid" "$file" "$out"
"$py" tests/f16_example_check.py "$file" "$out/summary.json"
