#!/usr/bin/env bash
# SIGTERM and SIGHUP during a large write (issue 10 item 10): the temporary
# file (".<name>.tmp-<pid>-<n>", tens of MB) is removed, the earlier output is
# intact and the process ends by the signal (exit status 128 + signal).
# (SIGINT is covered by tests/core/temp_files_test.cpp: a background job of a
# non-interactive shell starts with SIGINT ignored, which podid respects.)
# Usage: bash tests/cli/hostile_signals.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
cd "$out"
printf 'precious\n' >sim.csv
for signal in TERM HUP; do
  # 60 s of simulated time: 300001 rows, ~45 MB of CSV, written for ~1 s.
  "$podid" simulate "$root/examples/beam.toml" --no-noise --set time.duration=60 \
    -o sim.csv >stdout 2>stderr &
  pid=$!
  seen=0
  for _ in $(seq 1 3000); do
    if ls -A | grep -q '^\.sim\.csv\.tmp-'; then
      seen=1
      break
    fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.01
  done
  [ $seen -eq 1 ] || fail "SIG$signal: no temporary seen (the write finished too fast?)"
  sleep 0.05  # the write is under way
  kill -"$signal" "$pid"
  wait "$pid"
  rc=$?
  expected=$((128 + $(kill -l "$signal")))
  [ $rc -eq $expected ] || fail "SIG$signal: exit $rc, expected $expected ($(cat stderr))"
  [ "$(cat sim.csv)" = precious ] || fail "SIG$signal: the earlier output changed"
  [ "$(ls -A | grep -c '\.tmp-')" -eq 0 ] || fail "SIG$signal: temporary left: $(ls -A)"
done
echo "hostile signals: ok"
