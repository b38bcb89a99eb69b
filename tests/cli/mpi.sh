#!/usr/bin/env bash
# podid under mpirun (issue 14): 2 ranks give the same landscape CSV byte for
# byte and the same multistart identification as one process; rank 0 writes;
# a failure is reported on every rank; commands that do not spread their
# work refuse to run on several ranks. Skipped when mpirun is missing or
# podid was built without MPI (the sanitizer preset).
# Usage: bash tests/cli/mpi.sh PODID (from the repo root).
set -u
podid="$1"
. tests/support/cli.sh
cli_scratch
command -v mpirun >/dev/null || { echo "mpi: mpirun not found, skipped"; exit 0; }
# CI runs as root; 2 ranks on any number of cores.
mpi() { OMPI_MCA_rmaps_base_oversubscribe=1 mpirun --allow-run-as-root --oversubscribe -n 2 "$@"; }

# Built with MPI? Then `modes` refuses several ranks (exit 1 on every rank).
mpi "$podid" modes examples/beam.toml >"$out/modes.out" 2>"$out/modes.err"
if [ $? -eq 0 ]; then
  echo "mpi: podid built without MPI, skipped"
  exit 0
fi
[ "$(grep -c 'runs as one process: start it without mpirun' "$out/modes.err")" -eq 2 ] ||
  fail "modes on 2 ranks: $(cat "$out/modes.err")"

case_args=(examples/beam.toml --measured examples/measured_knl50_T0.1.csv)
# Landscape: the same CSV, byte for byte; one report (rank 0).
"$podid" landscape "${case_args[@]}" --param knl --range 0:200:21 --objective full,time-free --threads 1 \
  -o "$out/one.csv" >"$out/one.out" 2>/dev/null || fail "landscape, one process"
mpi "$podid" landscape "${case_args[@]}" --param knl --range 0:200:21 --objective full,time-free --threads 1 \
  -o "$out/two.csv" >"$out/two.out" 2>/dev/null || fail "landscape, 2 ranks"
cmp -s "$out/one.csv" "$out/two.csv" || fail "landscape CSVs differ: $(diff "$out/one.csv" "$out/two.csv" | head -5)"
[ "$(grep -c '^landscape: completed, 21 points' "$out/two.out")" -eq 1 ] || fail "not one report: $(cat "$out/two.out")"
# Identify --multistart: the same best point and history.
"$podid" identify "${case_args[@]}" --objective time-free --multistart 5 --threads 1 \
  --json "$out/one.json" >"$out/id1.out" 2>/dev/null || fail "identify, one process"
mpi "$podid" identify "${case_args[@]}" --objective time-free --multistart 5 --threads 1 \
  --json "$out/two.json" >"$out/id2.out" 2>/dev/null || fail "identify, 2 ranks"
[ "$(wc -l <"$out/id2.out")" -eq 1 ] || fail "identify printed $(wc -l <"$out/id2.out") lines"
python3 - "$out/one.json" "$out/two.json" <<'PY' || fail "identify results differ"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
a.pop("wall_time_s"); b.pop("wall_time_s")
assert a == b, [k for k in a if a[k] != b.get(k)]
PY
# A failure on every rank: exit 2 everywhere, no file.
mpi "$podid" landscape "${case_args[@]}" --param knl --range 0:200:4 --objective full \
  --set initial.static_tip_force=0 -o "$out/fail.csv" >/dev/null 2>"$out/fail.err"
[ $? -ne 0 ] || fail "a landscape where every point fails succeeded"
[ ! -e "$out/fail.csv" ] || fail "a failed landscape wrote its CSV"
[ "$(grep -c 'none of the 4 points succeeded' "$out/fail.err")" -ge 2 ] || fail "not reported on every rank: $(cat "$out/fail.err")"
echo "mpi: landscape and identify on 2 ranks equal one process"
