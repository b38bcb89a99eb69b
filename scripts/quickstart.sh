#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to the main job: installs what is
# missing, builds podid in Release, and identifies the reference beam's cubic
# stiffness (knl, true value 50) from the shared-format measured data in
# examples/, with the paper's wavelet objective, printing the report and
# writing the plots.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build-fftw.sh || echo "podid: scripts/build-fftw.sh failed: podid uses Debian's libfftw3"
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
podid=build/release/apps/podid
out=out/quickstart
mkdir -p "$out"
echo
echo "== podid modes examples/beam.toml"
"$podid" modes examples/beam.toml --count 4
echo
echo "== podid identify (1 s record, wavelet objective, start knl = 25)"
"$podid" identify examples/beam.toml --measured examples/measured_knl50_T1.0.csv \
  --objective wavelet --start knl=25 --report \
  --json "$out/identify.json" --plot-dir "$out"
echo
echo "== podid landscape (knl 0..200, full / time-free / wavelet)"
"$podid" landscape examples/beam.toml --measured examples/measured_knl50_T1.0.csv \
  --param knl --range 0:200:401 -o "$out/landscape.csv" --plot "$out/landscape.png"
echo
echo "Results in $out/: identify.json, signals.csv, fig2a_start.png, fig2b_optimum.png,"
echo "convergence.png, ridge.png, landscape.csv, landscape.png"
