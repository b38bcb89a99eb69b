#!/usr/bin/env bash
# The installed package works for a consumer: installs the build in BUILD_DIR
# to a temporary prefix, then configures, builds and runs examples/consumer
# (find_package(podid), podid::podid) against that prefix only.
# Usage: bash tests/install/consumer.sh BUILD_DIR   (from the repo root)
set -euo pipefail
build=$(cd "$1" && pwd)
root=$(pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log" \
  || { cat "$tmp/install.log"; fail "cmake --install $build"; }
[ -f "$tmp/prefix/lib/cmake/podid/podidConfig.cmake" ] || \
  [ -n "$(find "$tmp/prefix" -name podidConfig.cmake)" ] || fail "no podidConfig.cmake installed"

# The same compiler and, for a sanitizer build, the same instrumentation (the
# static libraries need the sanitizer runtime at link time).
cache="$build/CMakeCache.txt"
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$cache")
flags=()
if grep -q '^PODID_SANITIZE:BOOL=ON' "$cache"; then
  flags+=(-DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer"
          -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined")
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

cmake -S "$root/examples/consumer" -B "$tmp/consumer" "${generator[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "${flags[@]}" \
  >"$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; fail "configure the consumer"; }
grep -q "podid_DIR" "$tmp/consumer/CMakeCache.txt" || fail "podid_DIR not set"
grep "^podid_DIR" "$tmp/consumer/CMakeCache.txt" | grep -q "^podid_DIR:PATH=$tmp/prefix/" \
  || fail "found podid outside the install prefix: $(grep '^podid_DIR' "$tmp/consumer/CMakeCache.txt")"
cmake --build "$tmp/consumer" >"$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; fail "build the consumer"; }

"$tmp/consumer/podid_consumer" examples/beam.toml examples/measured_knl50_T0.1.csv >"$tmp/out" \
  || { cat "$tmp/out"; fail "podid_consumer exited $?"; }
cat "$tmp/out"
grep -q "^POM 1 holds" "$tmp/out" || fail "no POM energy line"
grep -q "^F(knl = 50) = " "$tmp/out" || fail "no objective line"
echo "PASS: consumer built and ran against $tmp/prefix"
