#!/usr/bin/env bash
# CI: a short fuzz smoke run of the readers (fuzz/run.sh) after the tests.
# Deterministic: a fixed number of inputs per target from seed 1, starting from
# the committed seeds only, so that CI runs the inputs this run was checked
# with here (about 20-40 s per target on the 2-core machine). Open-ended
# fuzzing is `bash fuzz/run.sh <seconds>`. Installs clang-14 and
# libclang-rt-14-dev when missing (Debian packages, as scripts/install-deps.sh does).
# Usage: bash .ci/fuzz-smoke.sh
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(clang-14 libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} > 0)); then
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
  echo "fuzz-smoke: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
start=$(date +%s)
build=build/fuzz-smoke
rm -rf "$build/corpus" "$build/artifacts"
status=0
# Runs per target: about 20-40 s each at the rates measured here (csv ~2000/s,
# case ~3400/s, mat ~2400/s, uff ~4700/s, model ~4000/s, wisdom ~10000/s under ASan + UBSan).
for spec in csv:60000 case:100000 mat:60000 uff:100000 model:100000 wisdom:200000; do
  PODID_FUZZ_BUILD="$build" PODID_FUZZ_RUNS="${spec#*:}" PODID_FUZZ_SEED=1 \
    bash fuzz/run.sh 0 "${spec%%:*}" || status=1
done
echo "fuzz-smoke: done in $(($(date +%s) - start)) s (build + csv, case, mat, uff, model, wisdom)"
exit $status
