#!/usr/bin/env bash
# The one-dof Duffing oscillator (1x1 imported matrices) against scipy's DOP853:
# tests/duffing_dop853.py. Usage: bash tests/cli/duffing_dop853.sh PODID (from the repo root).
set -eu
py=python3
python3 -c "import scipy" 2>/dev/null || py=/usr/bin/python3
"$py" tests/duffing_dop853.py "$1"
