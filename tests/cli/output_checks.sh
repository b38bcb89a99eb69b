#!/usr/bin/env bash
# Outputs checked before anything is computed, and results checked before
# anything is written:
#  - a read-only output file (0444, also through a symlink) and an output in
#    a read-only (0555) folder are refused, exit 1, the file's bytes
#    unchanged: also as root (CI), who passes access(W_OK) whatever the mode;
#  - an empty output path is refused, not taken for an option not given;
#  - a one-frequency grid is refused naming --fmin/--fmax/--voices;
#  - an input near the largest double: a reconstruction or amplitude that
#    overflows is exit 2 with its reason and no file, never inf in a CSV;
#  - --plot thins the frequencies as well as the times (bounded data file).
# Usage: bash tests/cli/output_checks.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
trap 'chmod -R u+w "$out"; rm -rf "$out"' EXIT  # the read-only folder too
cd "$out"
data="$root/tests/data/measured_knl50_T0.1.csv"
cp "$root/examples/beam.toml" case.toml

printf 'precious\n' >ro.csv
chmod 444 ro.csv
mkdir rodir
printf 'precious\n' >rodir/precious.csv
chmod 444 rodir/precious.csv
chmod 555 rodir
ln -s "$out/rodir/precious.csv" link.csv
sums() { md5sum ro.csv rodir/precious.csv; }
before=$(sums)

# refused NEEDLE COMMAND...: exit 1, one line matching NEEDLE, nothing
# computed (stdout empty), the read-only files unchanged, nothing new.
refused() {
  local needle="$1"
  shift
  cli_refused "$*" "^podid: error: $needle" "$@"
  [ "$(ls -A rodir)" = precious.csv ] || fail "$*: wrote in the read-only folder: $(ls -A rodir)"
  return 0
}
ro_file='cannot write ro.csv: the file is read-only'
ro_folder="cannot write rodir/new.csv: cannot create a temporary file in $out/rodir"
cwt=(cwt "$data" --channel w1)
refused "-o: $ro_file" "${cwt[@]}" -o ro.csv
refused "-o: cannot write link.csv: the file is read-only" "${cwt[@]}" -o link.csv
refused "-o: cannot write rodir/precious.csv: the file is read-only" \
  "${cwt[@]}" -o rodir/precious.csv
refused "-o: $ro_folder" "${cwt[@]}" -o rodir/new.csv
refused "--scalogram: $ro_file" "${cwt[@]}" --scalogram ro.csv
refused "--inverse: $ro_folder" "${cwt[@]}" --inverse rodir/new.csv
refused "--plot: cannot write link.csv: the file is read-only" "${cwt[@]}" --plot link.csv
refused "-o: $ro_file" simulate case.toml -o ro.csv
refused "-o: $ro_folder" pod "$data" -o rodir/new.csv
refused "--json: cannot write link.csv: the file is read-only" pod "$data" --json link.csv
land=(landscape case.toml -m "$data" --objective time-free --param knl --range 0:100:3)
refused "--plot: $ro_file" "${land[@]}" --plot ro.csv
refused "--json: $ro_folder" "${land[@]}" --json rodir/new.csv
ident=(identify case.toml -m "$data" --objective time-free --max-evaluations 2)
refused "--json: $ro_file" "${ident[@]}" --json ro.csv
refused "--plot-dir: expected a writable folder" "${ident[@]}" --plot-dir rodir/figs
if [ "$(id -u)" -eq 0 ]; then
  # Root is refused by the mode itself, and the message says so.
  "$podid" "${cwt[@]}" -o ro.csv 2>stderr >/dev/null
  grep -q "the file is read-only (mode 0444)" stderr || fail "root, 0444: $(cat stderr)"
  "$podid" "${cwt[@]}" -o rodir/new.csv 2>stderr >/dev/null
  grep -q "the folder is read-only (mode 0555)" stderr || fail "root, 0555: $(cat stderr)"
fi
# A writable file and folder still are written (the mode is kept).
printf 'old\n' >rw.csv
chmod 640 rw.csv
"$podid" "${cwt[@]}" -o rw.csv >/dev/null 2>stderr || fail "-o rw.csv: $(cat stderr)"
head -1 rw.csv | grep -q '^t,f_Hz,' || fail "rw.csv not written"
[ "$(stat -c %a rw.csv)" = 640 ] || fail "rw.csv mode $(stat -c %a rw.csv)"

# An empty path is an error naming the option (it used to write nothing, exit 0).
for option in -o --scalogram --inverse --plot; do
  refused "--.*: expected a file path, got an empty one" "${cwt[@]}" "$option" ''
done
refused "--output: expected a file path, got an empty one" simulate case.toml -o ''
refused "--json: expected a file path, got an empty one" pod "$data" --json ''
refused "--plot: expected a file path, got an empty one" "${land[@]}" --plot ''
refused "--plot-dir: expected a folder path, got an empty one" "${ident[@]}" --plot-dir ''
"$podid" "${cwt[@]}" --plot '' 2>stderr >/dev/null
grep -q "^podid: error: --plot: expected a file path, got an empty one" stderr \
  || fail "--plot '': $(cat stderr)"

# One frequency (10 to 10.0000000001 Hz at 32 voices) is no grid: refused
# before the transform, naming the options (the synchrosqueezing and the
# inverse used to fail naming the library's scalogram).
for extra in "" --synchrosqueeze "--inverse inv.csv"; do
  # shellcheck disable=SC2086
  refused "--fmin/--fmax/--voices: expected a band of at least 2 frequencies" \
    "${cwt[@]}" --fmin 10 --fmax 10.0000000001 $extra
done
[ ! -e inv.csv ] || fail "one frequency: inv.csv written"
"$podid" "${cwt[@]}" --fmin 10 --fmax 10.25 -o two.csv >/dev/null 2>stderr \
  || fail "two frequencies: $(cat stderr)"

# Near the largest double (a 50 Hz tone of amplitude A, 2000 samples at 1 kHz):
# every number written is finite, or the command fails with its reason.
tone() {
  awk -v a="$1" 'BEGIN { print "t,x"; for (i = 0; i < 2000; ++i) {
    t = i / 1000; printf "%.17g,%.17g\n", t, a * sin(2 * 3.141592653589793 * 50 * t) } }' >"$2"
}
finite_csv() {  # no inf anywhere in the file (NaN marks screened IFs: allowed)
  ! tail -n +2 "$1" | grep -qi 'inf'
}
tone 1e308 big.csv
"$podid" cwt big.csv --channel x --fmin 20 --fmax 200 --inverse big_inv.csv \
  >stdout 2>stderr
rc=$?
[ $rc -eq 0 ] || fail "1e308 --inverse: exit $rc: $(cat stderr)"
finite_csv big_inv.csv || fail "1e308 --inverse wrote inf"
# The in-band 50 Hz tone comes back: peak within 1 % of 1e308.
awk -F, 'NR > 500 && NR < 1500 { v = $2 < 0 ? -$2 : $2; if (v > m) m = v }
  END { exit !(m > 0.99e308 && m < 1.01e308) }' big_inv.csv \
  || fail "1e308 --inverse: peak not 1e308: $(sort -t, -k2 -g big_inv.csv | tail -1)"
tone 1.79e308 max.csv
for extra in --synchrosqueeze "--inverse max_inv.csv"; do
  # shellcheck disable=SC2086
  "$podid" cwt max.csv --channel x --fmin 20 --fmax 200 -o max_ridge.csv $extra \
    >stdout 2>stderr
  rc=$?
  if [ $rc -eq 0 ]; then
    finite_csv max_ridge.csv || fail "1.79e308 $extra: inf in the ridge CSV"
    [ ! -e max_inv.csv ] || finite_csv max_inv.csv || fail "1.79e308 $extra: inf in --inverse"
    grep -qi 'amplitude inf' stdout && fail "1.79e308 $extra: printed an inf amplitude"
  else
    [ $rc -eq 2 ] || fail "1.79e308 $extra: exit $rc, expected 0 or 2: $(cat stderr)"
    grep -q "overflowed double precision" stderr && grep -q "peak magnitude is 1.79e+308" stderr \
      || fail "1.79e308 $extra: message: $(cat stderr)"
    [ ! -e max_ridge.csv ] && [ ! -e max_inv.csv ] || fail "1.79e308 $extra: a file was written"
  fi
  rm -f max_ridge.csv max_inv.csv
done

# --plot thins the frequencies too: 20000 bins give at most 500 rows of at
# most 1000 times in gnuplot's data (it was 20000 rows: gigabytes in gnuplot).
PODID_GNUPLOT=/nonexistent "$podid" cwt "$data" --channel w1 --fmin 10 --fmax 400 --bins 20000 \
  --plot many.png >stdout 2>stderr || fail "--bins 20000 --plot: $(cat stderr)"
kept=$(ls -d many.png.gnuplot-*/)
rows=$(grep -c . "${kept}data0.txt")
[ "$rows" -le 500000 ] || fail "--plot data: $rows cells for 20000 bins"
distinct=$(awk 'NF == 3 { print $2 }' "${kept}data0.txt" | sort -u | wc -l)
[ "$distinct" -le 500 ] && [ "$distinct" -ge 400 ] || fail "--plot rows: $distinct frequencies"
echo "output checks: ok"
