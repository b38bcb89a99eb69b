#!/usr/bin/env bash
# Outputs under hostile or careless arguments (issue 10 items 3, 4, 11):
#  - an output that is the same file as an input (by any spelling, symlink or
#    hard link) is refused before anything is computed, exit 1, input intact;
#  - special targets: symlinks written through, modes kept, FIFOs, /dev/null
#    and /dev/stdout written in place;
#  - every output's folder is checked before the computation;
#  - argument errors exit 1 with one line prefixed "podid:".
# Usage: bash tests/cli/hostile_outputs.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
cd "$out"
cp "$root/examples/beam.toml" case.toml
cp "$root/tests/data/measured_knl50_T0.1.csv" data.csv
# A force file the case reads ([force] type = "file"): column F, zero force.
awk 'NR == 1 { print "t,F"; next } { split($0, c, ","); print c[1] ",0" }' data.csv >force.csv
force=(--set force.type=file --set force.file=force.csv --set force.column=F)
ln -s data.csv data_link.csv
ln data.csv data_hard.csv
mkdir plots
ln -s ../data.csv plots/signals.csv
sums() { md5sum case.toml data.csv force.csv; }
before=$(sums)

# expect_refused "what" COMMAND...: exit 1, one line naming the input, no
# output on stdout (nothing computed), every input intact.
expect_refused() {
  local what="$1"
  shift
  cli_refused "$what" "^podid: error: .*the same file" "$@"
}

expect_refused "simulate -o case" simulate case.toml -o case.toml
expect_refused "simulate -o ./case" simulate case.toml -o ./case.toml
expect_refused "simulate -o force file" simulate case.toml "${force[@]}" -o force.csv
grep -q "force file" stderr || fail "force file not named: $(cat stderr)"
expect_refused "pod -o data" pod data.csv -o data.csv
expect_refused "pod --json data (symlink)" pod data.csv --json data_link.csv
expect_refused "pod -o data (hard link)" pod data.csv -o data_hard.csv
expect_refused "pod -o data (input via link)" pod data_link.csv -o "$out/data.csv"
expect_refused "pod -o = --json" pod data.csv -o x.csv --json ./x.csv
expect_refused "cwt -o data" cwt data.csv --channel w6 -o data.csv
expect_refused "cwt --scalogram data" cwt data.csv --channel w6 --scalogram ./data.csv
expect_refused "cwt --plot data" cwt data.csv --channel w6 --plot data_link.csv
ident=(case.toml -m data.csv --objective time-free --max-evaluations 2)
expect_refused "identify --json measured" identify "${ident[@]}" --json data.csv
expect_refused "identify --json case" identify "${ident[@]}" --json case.toml
expect_refused "identify --json force" identify "${ident[@]}" "${force[@]}" --json force.csv
expect_refused "identify --plot-dir content" identify "${ident[@]}" --plot-dir plots
land=(case.toml -m data.csv --objective time-free --param knl --range 0:100:3)
expect_refused "landscape -o measured" landscape "${land[@]}" -o data.csv
expect_refused "landscape --json case" landscape "${land[@]}" --json case.toml
expect_refused "landscape --plot measured" landscape "${land[@]}" --plot data_hard.csv
# An imported model's matrix files are inputs too.
mkdir duffing
cp "$root"/examples/duffing/{duffing.toml,m.mtx,k.mtx,c.mtx} duffing/
duffing_sums=$(md5sum duffing/*)
expect_refused "simulate -o stiffness matrix" simulate duffing/duffing.toml -o duffing/k.mtx
grep -q "stiffness matrix file" stderr || fail "matrix file not named: $(cat stderr)"
expect_refused "simulate -o damping matrix" simulate duffing/duffing.toml -o ./duffing/c.mtx
[ "$(md5sum duffing/*)" = "$duffing_sums" ] || fail "an imported model file changed"

# Every output's folder is checked before the computation: no CSV written
# and then a failure on a bad --json path.
"$podid" landscape "${land[@]}" -o land.csv --json missing/land.json >stdout 2>stderr
rc=$?
[ $rc -eq 1 ] || fail "bad --json folder: exit $rc"
grep -q "^podid: error: --json: cannot write missing/land.json" stderr \
  || fail "bad --json folder message: $(cat stderr)"
[ ! -e land.csv ] && [ ! -s stdout ] || fail "bad --json folder: computed or wrote land.csv first"
"$podid" pod data.csv -o plots >stdout 2>stderr
[ $? -eq 1 ] && grep -q "^podid: error: -o: cannot write plots: it is a folder" stderr \
  || fail "output is a folder: $(cat stderr)"
"$podid" identify "${ident[@]}" --plot-dir data.csv >stdout 2>stderr
[ $? -eq 1 ] && grep -q "^podid: error: --plot-dir: expected a folder" stderr && [ ! -s stdout ] \
  || fail "--plot-dir is a file: $(cat stderr)"
"$podid" cwt data.csv --channel w6 -o r.csv --plot nofolder/x.png >stdout 2>stderr
[ $? -eq 1 ] && [ ! -e r.csv ] && [ ! -s stdout ] || fail "cwt bad --plot folder: $(cat stderr)"

# Special targets.
printf 'old\n' >target.csv
chmod 600 target.csv
ln -s target.csv out_link.csv
"$podid" pod data.csv -o out_link.csv >/dev/null 2>stderr || fail "pod -o symlink: $(cat stderr)"
[ -L out_link.csv ] || fail "the symlink was replaced"
head -1 target.csv | grep -q '^t,v1' || fail "the symlink's target was not written"
[ "$(stat -c %a target.csv)" = 600 ] || fail "mode 0600 became $(stat -c %a target.csv)"
"$podid" pod data.csv -o /dev/null >/dev/null 2>stderr || fail "-o /dev/null: $(cat stderr)"
[ -c /dev/null ] || fail "/dev/null is no longer a device"
mkfifo fifo
cat fifo >from_fifo &
reader=$!
"$podid" pod data.csv -o fifo >/dev/null 2>stderr || fail "-o FIFO: $(cat stderr)"
wait $reader
[ -p fifo ] || fail "the FIFO was replaced"
[ "$(wc -l <from_fifo)" -eq "$(wc -l <data.csv)" ] || fail "FIFO output incomplete"
# /dev/stdout redirected to a file: the report and then the CSV, in order,
# and /dev/stdout itself untouched (as root it used to become a regular file).
stdout_kind=$(stat -c %F /dev/stdout)
"$podid" pod data.csv -o /dev/stdout >both.txt 2>stderr || fail "-o /dev/stdout: $(cat stderr)"
[ "$(stat -c %F /dev/stdout)" = "$stdout_kind" ] || fail "/dev/stdout was replaced"
head -1 both.txt | grep -q '^data.csv: 6 channels' || fail "report not first: $(head -1 both.txt)"
grep -q '^t,v1,' both.txt || fail "CSV not written to /dev/stdout"
[ "$(grep -c '^[0-9.e+-]*,' both.txt)" -eq "$(($(wc -l <data.csv) - 1))" ] \
  || fail "CSV rows on /dev/stdout: $(grep -c '^[0-9.e+-]*,' both.txt)"
"$podid" pod data.csv -o /dev/stdout | grep -q '^t,v1,' || fail "-o /dev/stdout into a pipe"
ls -A | grep -q '\.tmp-' && fail "temporary left: $(ls -A)"

# Argument errors: exit 1, one line, "podid: error:", no 309-digit number.
expect_argument_error() {
  local what="$1" needle="$2"
  shift 2
  "$podid" "$@" >stdout 2>stderr
  local rc=$?
  [ $rc -eq 1 ] || fail "$what: exit $rc, expected 1"
  [ "$(wc -l <stderr)" -eq 1 ] || fail "$what: $(wc -l <stderr) lines: $(cat stderr)"
  grep -q "^podid: error: .*$needle" stderr || fail "$what: message: $(cat stderr)"
  [ "$(wc -c <stderr)" -lt 200 ] || fail "$what: message too long: $(cat stderr)"
}
expect_argument_error "no command" "A subcommand is required"
expect_argument_error "missing case" "case is required" simulate
expect_argument_error "unknown option" "not expected: --bogus" simulate case.toml --bogus
expect_argument_error "--pom 0" '--pom: expected an integer in \[1, 1000000\], got "0"' \
  cwt data.csv --pom 0
expect_argument_error "--pom beyond the data's modes" \
  "cwt --pom: expected 1..6 (the data's POD modes), got 1000" \
  cwt data.csv --pom 1000
expect_argument_error "--coi-factor 11" '--coi-factor: expected a number in \[0, 10\], got "11"' \
  cwt data.csv --channel w1 --coi-factor 11
# Real options name themselves, as the integer ones do (the library's own
# checks would name FrequencyGrid.min_frequency_Hz, not --fmin).
expect_argument_error "cwt --fmin nan" '--fmin: expected a finite number > 0, got "nan"' \
  cwt data.csv --channel w1 --fmin nan
expect_argument_error "cwt --omega0 4" '--omega0: expected a number in \[5, 100\], got "4"' \
  cwt data.csv --channel w1 --omega0 4
expect_argument_error "cwt --penalty -1" '--penalty: expected a finite number >= 0, got "-1"' \
  cwt data.csv --channel w1 --penalty -1
# --max-memory's bound is the option's (the library's budget would take 0.5 MB
# and name CwtOptions.memory_budget_bytes for 0).
expect_argument_error "cwt --max-memory 0.5" '--max-memory: expected a number in \[1, 16777216\], got "0.5"' \
  cwt data.csv --channel w1 --max-memory 0.5
expect_argument_error "cwt --max-memory nan" '--max-memory: expected a number in \[1, 16777216\], got "nan"' \
  cwt data.csv --channel w1 --max-memory nan
# The grid's and the ridges' bounds are the options' too (the library's
# would name FrequencyGrid.voices_per_octave, RidgeOptions.ridges...).
expect_argument_error "cwt --voices 0" '--voices: expected an integer in \[1, 1024\], got "0"' \
  cwt data.csv --channel w1 --voices 0
expect_argument_error "plan --voices 2000" '--voices: expected an integer in \[1, 1024\], got "2000"' \
  plan --samples 1000 --fs 100 --voices 2000
expect_argument_error "plan --bins 1" '--bins: expected an integer in \[2, 100000\], got "1"' \
  plan --samples 1000 --fs 100 --bins 1
expect_argument_error "cwt --ridges 17" '--ridges: expected an integer in \[1, 16\], got "17"' \
  cwt data.csv --channel w1 --ridges 17
expect_argument_error "cwt --threads 257" '--threads: expected an integer in \[1, 256\], got "257"' \
  cwt data.csv --channel w1 --threads 257
expect_argument_error "cwt --fmin above --fmax" '--fmin: expected a frequency below --fmax (10 Hz), got 100 Hz' \
  cwt data.csv --channel w1 --fmin 100 --fmax 10
expect_argument_error "plan --fmin above Nyquist" \
  '--fmin: expected a frequency below the Nyquist frequency of a record of step 0.01 s (50 Hz), got 60 Hz' \
  plan --samples 1000 --fs 100 --fmin 60 --fmax 80
expect_argument_error "cwt --voices x octaves" \
  '--voices/--fmin/--fmax: expected at most 100000 frequencies (--voices x octaves), got 1024 x ' \
  cwt data.csv --channel w1 --voices 1024 --fmin 1e-300 --fmax 100
expect_argument_error "pod --energy 0" '--energy: expected a number in (0, 1\], got "0"' \
  pod data.csv --energy 0
expect_argument_error "plan --omega0 1e400" '--omega0: expected a number in \[5, 100\], got "1e400"' \
  plan --samples 1000 --fs 100 --omega0 1e400
expect_argument_error "--modes -1" "--modes: expected an integer in \[0, 1000000\]" \
  pod data.csv --modes -1
expect_argument_error "--count x" "--count: expected an integer" modes case.toml --count x
expect_argument_error "identify --modes 0" "--modes: expected an integer in \[1, 1000\]" \
  identify "${ident[@]}" --modes 0
expect_argument_error "identify --threads 1025" '--threads: expected an integer in \[0, 1024\], got "1025"' \
  identify "${ident[@]}" --threads 1025
expect_argument_error "identify --ridge-snr 2000" '--ridge-snr: expected a number in \[0, 1000\], got "2000"' \
  identify "${ident[@]}" --ridge-snr 2000
expect_argument_error "identify --min-signal nan" '--min-signal: expected a number in \[0, 0.999\], got "nan"' \
  identify "${ident[@]}" --min-signal nan
expect_argument_error "identify --seed -1" '--seed: expected an integer in \[0, 9223372036854775807\], got "-1"' \
  identify "${ident[@]}" --seed -1
expect_argument_error "identify --xtol abc" '--xtol: expected a finite number > 0, got "abc"' \
  identify "${ident[@]}" --xtol abc
expect_argument_error "landscape --threads 1025" '--threads: expected an integer in \[0, 1024\], got "1025"' \
  landscape case.toml -m data.csv --param knl --range 0:1:2 --threads 1025
expect_argument_error "a control character" 'not expected: \\x1b\[2J' \
  simulate case.toml $'\e[2J'
# A full disk behind stdout: the printed results are lost, exit 1 with a line.
if [ -w /dev/full ]; then
  "$podid" modes case.toml >/dev/full 2>"$out/full.err"
  rc=$?
  [ $rc -eq 1 ] || fail "stdout on /dev/full: exit $rc, expected 1"
  grep -q "^podid: error: standard output: expected the results written, got a write error" \
    "$out/full.err" || fail "stdout on /dev/full: $(cat "$out/full.err")"
fi
"$podid" --help >/dev/null || fail "--help: exit $?"
"$podid" pod --help | grep -q 'INT in \[0, 1000000\]' || fail "pod --help lacks the --modes bound"
"$podid" --version | grep -q '^podid ' || fail "--version"
echo "hostile outputs: ok"
