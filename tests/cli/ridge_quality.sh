#!/usr/bin/env bash
# The wavelet (IF) term's two statistical-quality checks (docs/cli.md,
# "podid identify"):
#  - a ridge band wholly outside the passband of --lowpass/--highpass/
#    --bandpass (or the case's [data] filter) is refused: exit 1, one line
#    naming both options and their values, nothing computed; a band partly
#    outside gets a note;
#  - a measured ridge compared over a handful of samples gets a note with
#    the count and the total;
#  - the shipped examples (examples/beam.toml with the 1 s record, one or
#    two modes, Morlet or Morse) give neither note.
# Usage: bash tests/cli/ridge_quality.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
cd "$out"
cp "$root/examples/beam.toml" case.toml
cp "$root/examples/measured_knl50_T1.0.csv" data.csv
cp "$root/examples/measured_knl50_T0.1.csv" short.csv
sums() { md5sum case.toml data.csv short.csv; }
before=$(sums)
identify=(identify case.toml -m data.csv --objective wavelet --start knl=25 --max-evaluations 3)
landscape=(landscape case.toml -m data.csv --objective wavelet --param knl --range 40:60:3 --threads 1)

refused() {
  local needle="$1"
  shift
  cli_refused "$*" "^podid: error: $needle" "$@"
}

# A band beyond the filter's cutoff, in identify and landscape.
refused "--fmin/--fmax: expected a ridge band reaching into the passband of --lowpass 50 (below 50 Hz: the filter conditions the measured and the simulated records alike, and beyond its cutoff both hold only its skirt), got 100..200 Hz, entirely above it$" \
  "${identify[@]}" --lowpass 50 --fmin 100 --fmax 200
refused "--fmin/--fmax: expected a ridge band reaching into the passband of --lowpass 50 " \
  "${landscape[@]}" --lowpass 50 --fmin 100 --fmax 200
# The cutoff itself counts as beyond, whatever the order.
refused "--fmin/--fmax: .*, got 50..200 Hz, entirely above it$" \
  "${identify[@]}" --lowpass 50 --filter-order 1 --fmin 50 --fmax 200
refused "--fmin/--fmax: expected a ridge band reaching into the passband of --highpass 150 (above 150 Hz: .*got 10..120 Hz, entirely below it$" \
  "${identify[@]}" --highpass 150
refused "--mode-band 2: expected a ridge band reaching into the passband of --bandpass 5:100 (5..100 Hz: .*got 150..400 Hz, entirely above it$" \
  "${identify[@]}" --bandpass 5:100 --modes 2 --mode-band 2=150:400
# The filter of the case's [data] is named by its keys.
refused "--fmin/--fmax: expected a ridge band reaching into the passband of \[data\] filter = \"lowpass\", cutoff = 50 of case.toml (below 50 Hz" \
  "${identify[@]}" --set 'data.filter="lowpass"' --set data.cutoff=50 --fmin 100 --fmax 200

# A band partly beyond the cutoff: a note, and the run goes on.
"$podid" "${identify[@]}" --lowpass 80 >stdout 2>stderr || fail "identify --lowpass 80: exit $? ($(cat stderr))"
grep -q "^podid: note: mode 1: 0.585 of the ridge band's 3.58 octaves (10..120 Hz; ridge.cwt.frequencies, --fmin/--fmax), 16.3 %, lie above the data's lowpass cutoff 80 Hz (order 4; data.filter, --lowpass), where the filter leaves both records only its skirt: keep the band inside the passband, e.g. 10..80 Hz$" stderr \
  || fail "identify --lowpass 80: no note of the band cut: $(cat stderr)"
grep -q "^identify (LN_BOBYQA, dU + dS + dIF)" stdout || fail "identify --lowpass 80: $(cat stdout)"

# A handful of ridge samples: the 0.1 s record from 30 Hz (shorter than the
# cone at 10 Hz) keeps 17 samples inside the cone at the ridge's 40 Hz, one
# wavelet duration.
"$podid" identify case.toml -m short.csv --objective wavelet --fmin 30 --start knl=25 --max-evaluations 3 \
  --json short.json >stdout 2>stderr || fail "identify 0.1 s --fmin 30: exit $? ($(cat stderr))"
compared=$(grep -Eo '"samples_compared": *[0-9]+' short.json | grep -Eo '[0-9]+$')
grep -Eq "^podid: note: mode 1: only $compared of the ridge's [0-9]+ samples are compared \(samples_compared: inside the cone of influence and above the noise\), [0-9.e-]+ s of the 0.1 s record: [0-9.e-]+ wavelet durations at the ridge's [0-9.]+ Hz \([0-9.e-]+ s each, over which its IFs are correlated\), fewer than 4, so the IF term rests on a handful of independent values; for a sounder fit give a longer record, a shorter wavelet \(--omega0 below 6, 5 at least\)$" stderr \
  || fail "identify 0.1 s --fmin 30: no note of the few samples ($compared): $(cat stderr)"

# The shipped examples: quiet.
for extra in "" "--modes 2" "--wavelet morse" "--modes 2 --wavelet morse"; do
  # shellcheck disable=SC2086
  "$podid" "${landscape[@]}" $extra >stdout 2>stderr || fail "landscape $extra: exit $? ($(cat stderr))"
  if grep -E "samples are compared|of the ridge band's" stderr; then
    fail "landscape $extra on the 1 s record: a quality note"
  fi
done
[ "$(sums)" = "$before" ] || fail "an input changed"
echo "ridge_quality: ok"
