#!/usr/bin/env bash
# Installs the Debian packages podid needs (only those missing). Run as root,
# or as a user with sudo. Every dependency is a Debian package.
set -euo pipefail
packages=(
  gcc g++ make cmake ninja-build pkg-config git
  libeigen3-dev libspectra-dev libmetis-dev libfftw3-dev libgsl-dev libnlopt-cxx-dev libmatio-dev libhdf5-dev zlib1g-dev
  libtomlplusplus-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox python3 python3-numpy python3-scipy python3-pywt
  python3-dev pybind11-dev python3-pytest python3-venv python3-setuptools python3-matplotlib
  libopenmpi-dev openmpi-bin
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "podid: all ${#packages[@]} Debian packages present"
  exit 0
fi
sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "podid: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
