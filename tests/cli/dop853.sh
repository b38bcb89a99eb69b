#!/usr/bin/env bash
# podid against models written independently and integrated by scipy's DOP853:
# the one-dof Duffing oscillator (tests/duffing_dop853.py) and the pinned beam
# with a point mass measured in acceleration (tests/beam_dop853.py).
# Usage: bash tests/cli/dop853.sh PODID (from the repo root).
set -eu
. tests/support/cli.sh
cli_python "for the DOP853 references (Debian's python3-scipy)" numpy scipy.integrate
"$py" tests/duffing_dop853.py "$1"
"$py" tests/beam_dop853.py "$1"
