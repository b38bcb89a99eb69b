#!/usr/bin/env bash
# CI: a short fuzz smoke run of the readers (fuzz/run.sh, 30 s per target by
# default) after the tests. Installs clang-14 and libclang-rt-14-dev when
# missing (Debian packages, as scripts/install-deps.sh does).
# Usage: bash .ci/fuzz-smoke.sh [seconds per target]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-${PODID_FUZZ_SECONDS:-30}}"
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
PODID_FUZZ_BUILD=build/fuzz-smoke bash fuzz/run.sh "$seconds" csv case mat
echo "fuzz-smoke: done in $(($(date +%s) - start)) s (build + ${seconds} s per target)"
