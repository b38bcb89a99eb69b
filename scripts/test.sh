#!/usr/bin/env bash
# Builds podid (preset "default", RelWithDebInfo) and runs the whole test suite.
# Both presets carry line tables only (-g1): sanitizer reports and backtraces
# keep file:line, and the compilation takes 25-37 % less time than with -g (a
# full variable view is a Debug build's job).
# Usage: bash scripts/test.sh [asan]
#   PODID_WERROR=ON makes warnings errors (CI sets it).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-default}"
bash scripts/install-deps.sh
bash scripts/build-fftw.sh || echo "podid: scripts/build-fftw.sh failed: podid uses Debian's libfftw3"
cmake --preset "$preset" -DPODID_WERROR="${PODID_WERROR:-OFF}" >/dev/null
cmake --build --preset "$preset" -j "$(nproc)"
ctest --preset "$preset" -j "$(nproc)" --timeout 900
