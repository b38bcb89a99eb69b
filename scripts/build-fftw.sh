#!/usr/bin/env bash
# Builds double-precision FFTW from Debian's own source package (fftw3, the
# version of the installed libfftw3-dev) with the x86-64 SIMD codelets that
# Debian's binary package leaves out for portability: AVX2 with FMA, and
# AVX-512 (Debian enables SSE2 and AVX only). FFTW picks its codelets at run
# time from cpuid, so the library still runs on any x86-64 machine. It goes to
# build/fftw-simd as a static, position-independent library, which
# CMakePresets.json searches before the system's. Not hand-written
# infrastructure: Debian's FFTW, configured for speed instead of for the
# oldest CPU.
#
# Built by default on Intel CPUs and on AMD CPUs from Zen 5 on (family 26 and
# later; PODID_FFTW_SIMD=auto). On a Zen 5 EPYC (AVX-512 at full width) fCWT's
# case ran 1.15-1.26x faster with measured plans and 1.13-1.21x at 10^4 with
# estimated ones, 0.86x at 10^5 (docs/benchmark-log.md, "Narrow bands' blocks
# as shorter inverses, and FFTW's codelets on a Zen 5"; 1.00x since the D = 1
# scales split, 93.6 against 94.0 ms: "The D = 1 scales split into 8
# inverses of P / 8"). On an Intel
# Xeon (family 6 model 207, AVX-512) the transforms are faster with it, with
# FFTW_ESTIMATE's plans too (the CWT of fCWT's case 1.04-1.32x, the Silverbox
# evaluation 1.36x), but on an AMD Zen 4 FFTW_ESTIMATE picked slower plans
# among the new codelets (the Silverbox evaluation 0.85x), and estimated plans
# are what every process uses until `podid plan` has run (docs/benchmark-log.md,
# "FFTW with its AVX2 and AVX-512 codelets"); on a Zen 3 the CWT was slower
# with estimated plans (0.60-0.69x) and no faster with measured ones
# ("FFTW's AVX2 codelets on a Zen 3 EPYC"). PODID_FFTW_SIMD=ON builds it on
# any x86-64 CPU, OFF never; any other value is an error (exit 1). Whatever
# stops it (not x86-64, Debian's source archive out of reach, a failed build)
# leaves podid on Debian's libfftw3-dev, as without this script: it says why
# and exits 0. A finished build is kept (build/fftw-simd/podid-stamp) and not
# repeated.
# Usage: bash scripts/build-fftw.sh
set -euo pipefail
cd "$(dirname "$0")/.."
prefix="$PWD/build/fftw-simd"
flags=(--enable-sse2 --enable-avx --enable-avx2 --enable-avx512 --enable-fma)
skip() {
  echo "podid: FFTW with AVX2/AVX-512 not built ($1): without build/fftw-simd, podid uses Debian's libfftw3"
  exit 0
}
choice=${PODID_FFTW_SIMD:-auto}
case "$choice" in
  auto | ON | OFF) ;;
  *) echo "podid: PODID_FFTW_SIMD: expected auto, ON or OFF, got '$choice'" >&2; exit 1 ;;
esac
[ "$choice" != OFF ] || skip "PODID_FFTW_SIMD=OFF"
[ "$(uname -m)" = x86_64 ] || skip "not x86-64"
if [ "$choice" = auto ]; then
  vendor=$(awk -F': *' '/^vendor_id/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || true)
  family=$(awk -F': *' '/^cpu family/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || true)
  case "$vendor" in
    GenuineIntel) ;;
    AuthenticAMD) [[ "$family" =~ ^[0-9]+$ ]] && ((family >= 26)) ||
      skip "an AMD CPU before Zen 5 (family ${family:-unknown}): PODID_FFTW_SIMD=ON builds it anyway" ;;
    *) skip "neither an Intel CPU nor an AMD Zen 5 or later: PODID_FFTW_SIMD=ON builds it anyway" ;;
  esac
fi
version=$(dpkg-query -W -f='${source:Version}' libfftw3-dev 2>/dev/null) || skip "no libfftw3-dev"
stamp="fftw3 $version ${flags[*]}"
if [ -f "$prefix/lib/libfftw3.a" ] && [ "$(cat "$prefix/podid-stamp" 2>/dev/null)" = "$stamp" ]; then
  echo "podid: FFTW $version with AVX2/AVX-512 present in $prefix"
  exit 0
fi
rm -rf "$prefix"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Debian's source archive for this release, through apt alone (its signed
# index checks the files): a sources list of our own, the system's untouched.
. /etc/os-release
[ -n "${VERSION_CODENAME:-}" ] || skip "no VERSION_CODENAME in /etc/os-release"
cat >"$work/sources" <<EOF
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $VERSION_CODENAME main
EOF
mkdir -p "$work/lists/partial" "$work/cache/archives/partial" "$work/src"
apt_options=(-o "Dir::Etc::SourceList=$work/sources" -o "Dir::Etc::SourceParts=/dev/null"
  -o "Dir::State::Lists=$work/lists" -o "Dir::Cache=$work/cache")
# Root's apt downloads as _apt, who cannot write in this folder.
if [[ $(id -u) -eq 0 ]]; then apt_options+=(-o "APT::Sandbox::User=root"); fi
apt-get "${apt_options[@]}" update -qq >"$work/log" 2>&1 || skip "apt-get update of the source index failed"
(cd "$work/src" && apt-get "${apt_options[@]}" source --download-only -qq "fftw3=$version") \
  >>"$work/log" 2>&1 || skip "apt-get source fftw3=$version failed"
upstream=${version#*:}  # no epoch in the file names
upstream=${upstream%-*}
tar -xzf "$work/src/fftw3_$upstream.orig.tar.gz" -C "$work/src" || skip "cannot unpack fftw3_$upstream.orig.tar.gz"
echo "podid: building FFTW $version with AVX2/AVX-512 codelets in $prefix (about 6 min on 2 cores)"
if ! (cd "$work/src/fftw-$upstream" &&
  ./configure --prefix="$prefix" --disable-shared --enable-static --with-pic \
    --disable-fortran --disable-doc "${flags[@]}" &&
  make -j "$(nproc)" && make install) >>"$work/log" 2>&1; then
  tail -n 20 "$work/log"
  rm -rf "$prefix"
  skip "the build failed (its log's end above)"
fi
echo "$stamp" >"$prefix/podid-stamp"
echo "podid: FFTW $version with AVX2/AVX-512 installed in $prefix"
