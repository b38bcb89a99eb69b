#!/usr/bin/env bash
# Every command and flag in docs/cli.md exists:
#  1. each example command (a line of a ```console block starting with
#     "$ podid", with "\" continuations) runs with this podid in a temporary
#     folder holding examples/ and tests/data/, and exits 0, or the status
#     written after it as a comment ("# exit 1");
#  2. each option named in the first column of an option table under a
#     "## `podid CMD`" heading appears in `podid CMD --help`.
# Usage: bash tests/cli/docs_examples.sh PODID   (from the repo root)
set -u
podid=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
doc=docs/cli.md
[ -x "$podid" ] || { echo "FAIL: no podid at $1" >&2; exit 1; }
[ -f "$doc" ] || { echo "FAIL: no $doc (run from the repo root)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin" "$work/run/tests"
ln -s "$podid" "$work/bin/podid"
cp -r examples "$work/run/examples"
cp -r tests/data "$work/run/tests/data"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# 1. The example commands.
awk '
  /^```console/ { inside = 1; next }
  /^```/        { inside = 0; cont = 0; next }
  inside && cont { printf " %s", $0; cont = ($0 ~ /\\$/); if (!cont) printf "\n"; next }
  inside && /^\$ podid/ { line = substr($0, 3); printf "%s", line; cont = (line ~ /\\$/); if (!cont) printf "\n" }
' "$doc" | sed 's/\\ / /g' >"$work/commands"
count=$(wc -l <"$work/commands")
[ "$count" -ge 6 ] || fail "only $count example commands found in $doc"
while IFS= read -r command; do
  expected=0
  if [[ "$command" =~ \#\ exit\ ([0-9]+)[[:space:]]*$ ]]; then expected=${BASH_REMATCH[1]}; fi
  (cd "$work/run" && PATH="$work/bin:$PATH" bash -c "$command" >"$work/out" 2>&1 </dev/null)
  status=$?
  if [ "$status" -ne "$expected" ]; then
    fail "'$command' exited $status, expected $expected"
    sed 's/^/    /' "$work/out" | tail -5 >&2
  else
    echo "ok (exit $status): $command"
  fi
done <"$work/commands"

# 2. The option tables: every `--flag` / `-x` of a table row's first cell.
awk '
  /^## `podid / { cmd = $3; gsub(/`/, "", cmd); next }
  /^## / { cmd = ""; next }
  cmd != "" && /^\| *`-/ {
    split($0, cells, "|"); cell = cells[2]
    while (match(cell, /`-[-a-zA-Z0-9]+/)) {
      print cmd, substr(cell, RSTART + 1, RLENGTH - 1); cell = substr(cell, RSTART + RLENGTH)
    }
  }
' "$doc" >"$work/flags"
flags=$(wc -l <"$work/flags")
[ "$flags" -ge 20 ] || fail "only $flags documented options found in $doc"
while read -r cmd flag; do
  if [ "$cmd" = "podid" ]; then help=$("$podid" --help 2>&1); else help=$("$podid" "$cmd" --help 2>&1); fi
  # CLI11 lists "-o,--output" and "--fmin FLOAT=10": the flag ends at a comma, space or '='.
  grep -Eq -- "(^|[ ,])$flag([ ,=]|$)" <<<"$help" || fail "podid $cmd: option $flag is documented but not in --help"
done <"$work/flags"

echo "$count example commands, $flags documented options checked, $failures failures"
[ "$failures" -eq 0 ]
