#!/usr/bin/env bash
# The module built in <build>/python installs into a fresh virtual environment
# (offline: --no-index, setuptools from the system) and works from there.
# Usage: venv_install.sh <python3> <build>/python
set -euo pipefail
python="$1"
package="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install -q --no-build-isolation --no-index "$package"
cd "$work"  # not the build tree: the installed copy must be the one imported
"$work/venv/bin/python" - <<'PY'
import numpy as np
import podid
assert podid.__file__.startswith(__import__("sys").prefix), podid.__file__
r = podid.pod(np.vstack([np.sin(np.arange(64.0)), np.cos(np.arange(64.0))]))
assert r.poms.shape == (2, 2), r.poms.shape
print("venv install: podid from", podid.__file__)
PY
