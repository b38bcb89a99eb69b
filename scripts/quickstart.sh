#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to the main job: installs what is
# missing, builds podid in Release and runs the reference case.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
podid=build/release/apps/podid
out=out/quickstart
mkdir -p "$out"
echo
echo "== podid modes examples/beam.toml"
"$podid" modes examples/beam.toml
echo
echo "== podid simulate examples/beam.toml -o $out/simulated.csv"
"$podid" simulate examples/beam.toml -o "$out/simulated.csv"
echo
echo "Output written to $out/"
