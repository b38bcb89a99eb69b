#!/usr/bin/env bash
# Failure paths of the podid executable (issue 7): unwritable outputs give a
# one-line error and exit 1, leave no partial file and never touch an earlier
# output; a landscape interrupted with SIGINT exits 130 and leaves its output
# absent (or, if it finished first, complete).
# Usage: bash tests/cli/failure_paths.sh PODID (from the repo root).
set -u
podid="$1"
case_file=examples/beam.toml
out=$(mktemp -d)
trap 'chmod -R u+w "$out"; rm -rf "$out"' EXIT
w="$out/outputs"  # only the outputs under test: stray temporaries show up here
mkdir "$w"
fail() { echo "FAIL: $*" >&2; exit 1; }

# The output folder is missing.
"$podid" simulate "$case_file" --no-noise -o /nonexistent/x.csv >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] || fail "missing folder: exit $rc, expected 1"
grep -q "cannot write /nonexistent/x.csv: cannot create a temporary file in /nonexistent" \
  "$out/stderr" || fail "missing folder message: $(cat "$out/stderr")"
[ "$(wc -l <"$out/stderr")" -eq 1 ] || fail "missing folder: more than one line on stderr"
[ ! -e /nonexistent/x.csv ] || fail "missing folder: a file appeared"

# A full disk: /dev/full (written in place, never replaced by a regular file).
if [ -c /dev/full ]; then
  "$podid" simulate "$case_file" --no-noise -o /dev/full >"$out/stdout" 2>"$out/stderr"
  rc=$?
  [ $rc -eq 1 ] || fail "/dev/full: exit $rc, expected 1"
  grep -q "cannot write /dev/full: No space left on device" "$out/stderr" \
    || fail "/dev/full message: $(cat "$out/stderr")"
  [ -c /dev/full ] || fail "/dev/full is no longer a character device"
fi

# An earlier output is untouched when the new one cannot be written: the case
# fails validation before anything is written...
printf 'precious\n' >"$w/sim.csv"
"$podid" simulate "$case_file" --set beam.length=-1 -o "$w/sim.csv" >/dev/null 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] || fail "invalid case: exit $rc, expected 1"
[ "$(cat "$w/sim.csv")" = precious ] || fail "invalid case: earlier output changed"
# ...and when the folder becomes read-only. Root writes there anyway, so as
# root (CI) podid runs as nobody (setpriv, util-linux), for whom $out is
# traversable and $w read-only; skipped only if neither works.
as_user=()
if [ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null; then
  as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
  chmod 755 "$out"
fi
chmod a-w "$w"
if ! "${as_user[@]}" touch "$w/probe" 2>/dev/null; then
  "${as_user[@]}" "$podid" simulate "$case_file" --no-noise -o "$w/sim.csv" >/dev/null 2>"$out/stderr"
  rc=$?
  [ $rc -eq 1 ] || fail "read-only folder: exit $rc, expected 1"
  grep -q "cannot write $w/sim.csv" "$out/stderr" || fail "read-only message"
  [ "$(cat "$w/sim.csv")" = precious ] || fail "read-only folder: earlier output changed"
else
  rm -f "$w/probe"
fi
chmod u+w "$w"
[ "$(ls -A "$w")" = sim.csv ] || fail "temporary files left: $(ls -A "$w")"

# A full disk in the middle of the file (RLIMIT_FSIZE, in a subshell): exit 1,
# the earlier output intact, no temporary left.
(
  ulimit -f 8  # 8 blocks of 512 bytes: the simulation's CSV is ~350 kB
  trap '' XFSZ
  exec "$podid" simulate "$case_file" --no-noise -o "$w/sim.csv"
) >/dev/null 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] || fail "file size limit: exit $rc, expected 1 ($(cat "$out/stderr"))"
grep -q "cannot write $w/sim.csv: File too large" "$out/stderr" \
  || fail "file size limit message: $(cat "$out/stderr")"
[ "$(cat "$w/sim.csv")" = precious ] || fail "file size limit: earlier output changed"
[ "$(ls -A "$w")" = sim.csv ] || fail "file size limit: temporary left: $(ls -A "$w")"

# --threads 0 takes OpenMP's count, with --threads' bound: OMP_NUM_THREADS=5000
# is named (it was reported as "threads: expected 0 to 1024, got 5000").
OMP_NUM_THREADS=5000 "$podid" landscape "$case_file" -m tests/data/measured_knl50_T1.0.csv \
  --param knl --range 40:60:3 --objective time-free -o "$w/omp.csv" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 1 ] || fail "OMP_NUM_THREADS=5000: exit $rc, expected 1"
grep -q "\-\-threads 0: expected OpenMP's thread count (OMP_NUM_THREADS, else the cores) of at most 1024, got OMP_NUM_THREADS=5000" \
  "$out/stderr" || fail "OMP_NUM_THREADS=5000 message: $(cat "$out/stderr")"
[ ! -e "$w/omp.csv" ] || fail "OMP_NUM_THREADS=5000: an output appeared"

# SIGINT during a long landscape: exit 130 and no output, or (had it finished)
# exit 0 and a complete output. The handler is installed once the measured
# data are decomposed, so SIGINT is repeated until the process ends.
"$podid" landscape "$case_file" -m tests/data/measured_knl50_T1.0.csv --param knl \
  --range 0:200:4001 --objective time-free -o "$w/landscape.csv" >"$out/stdout" 2>"$out/stderr" &
pid=$!
sleep 1
for _ in $(seq 1 120); do
  kill -INT "$pid" 2>/dev/null || break
  sleep 0.5
done
wait "$pid"
rc=$?
rc_landscape=$rc
if [ $rc -eq 130 ]; then
  [ ! -e "$w/landscape.csv" ] || fail "interrupted landscape left $w/landscape.csv"
  grep -q "no file written" "$out/stderr" || fail "interrupt message: $(cat "$out/stderr")"
elif [ $rc -eq 0 ]; then
  [ "$(wc -l <"$w/landscape.csv")" -eq 4002 ] || fail "landscape finished but its CSV is partial"
else
  fail "landscape after SIGINT: exit $rc ($(tail -1 "$out/stderr"))"
fi
ls -A "$w" | grep -q '\.tmp-' && fail "temporary file left after SIGINT"

# An ill-conditioned step matrix (998 of 1000 elements in the last 0.01 m) is
# a warning naming its estimate, not a failure: exit 0, the CSV written.
cat >"$out/uneven.toml" <<'TOML'
[beam]
youngs_modulus = 2.05e11
density = 7800.0
area = 0.196e-3
left = "pinned"
right = "pinned"
[[beam.segment]]
length = 0.99
elements = 2
[[beam.segment]]
length = 0.01
elements = 998
[time]
duration = 0.001
step = 1e-4
[sensors]
nodes = [2]
[force]
type = "harmonic"
node = 2
amplitude = 200.0
frequency = 50.0
TOML
"$podid" simulate "$out/uneven.toml" -o "$w/uneven.csv" >"$out/stdout" 2>"$out/stderr"
rc=$?
[ $rc -eq 0 ] || fail "ill-conditioned mesh: exit $rc, expected 0 ($(cat "$out/stderr"))"
grep -q "ill-conditioned: one solve's estimated relative error is 0.024, above 1e-04" \
  "$out/stderr" || fail "ill-conditioned mesh warning: $(cat "$out/stderr")"
[ "$(wc -l <"$w/uneven.csv")" -eq 12 ] || fail "ill-conditioned mesh: no complete CSV"
echo "failure paths: ok (landscape exit $rc_landscape)"
