# Sourced by the end-to-end scripts in tests/cli/ (not a test itself: CMake
# registers tests/cli/*.sh only). Run from the repository root.

# A scratch folder $out, removed on exit, and fail MESSAGE (exit 1).
cli_scratch() {
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
}
fail() { echo "FAIL: $*" >&2; exit 1; }

# py: a Python 3 that imports every module named (Debian's python3 first: it
# has python3-scipy); exit 77 (skipped) when none does, saying why ($1).
cli_python() {
  local why=$1 imports
  shift
  imports=$(printf 'import %s;' "$@")
  for py in /usr/bin/python3 python3; do
    if command -v "$py" >/dev/null && "$py" -c "$imports" 2>/dev/null; then return 0; fi
  done
  echo "SKIP: no Python with $* $why"
  exit 77
}

# real: the shared real data (../shared/realdata or $PODID_REALDATA); exit 77
# (skipped) when the file $1 below it is absent, naming the example ($2).
cli_realdata() {
  real="${PODID_REALDATA:-../shared/realdata}"
  if [ ! -f "$real/$1" ]; then
    echo "SKIP: $real/$1 is absent (the shared real data): $2 is not run"
    exit 77
  fi
}

# cli_refused LABEL PATTERN COMMAND...: "$podid" COMMAND exits 1 with one line
# on stderr matching the grep pattern PATTERN, prints nothing on stdout
# (nothing was computed before refusing), and the caller's `sums` (checksums
# of the files that must stay intact) still prints $before. Run in the
# caller's folder: it writes ./stdout and ./stderr.
cli_refused() {
  local label="$1" pattern="$2"
  shift 2
  "$podid" "$@" >stdout 2>stderr
  local rc=$?
  [ $rc -eq 1 ] || fail "$label: exit $rc, expected 1 ($(cat stderr))"
  [ "$(wc -l <stderr)" -eq 1 ] || fail "$label: not one line: $(cat stderr)"
  grep -q -- "$pattern" stderr || fail "$label: message: $(cat stderr)"
  [ ! -s stdout ] || fail "$label: computed before refusing: $(head -2 stdout)"
  [ "$(sums)" = "$before" ] || fail "$label: a file that must stay intact changed"
}
