#!/usr/bin/env bash
# The wavelet term's options of identify and landscape, and the wavelet
# options of cwt, refused where they would have been silently ignored or
# misread (an audit of 2026-12-01): each exit 1, one line naming the option,
# nothing computed, the inputs unchanged.
#  - --fmin, --fmax, --penalty, --mode-band, --ridge-snr and the wavelet's
#    options without an objective that has the IF term;
#  - --omega0 with --wavelet morse, --gamma/--beta with Morlet;
#  - a band narrower than one step of the ridge's grid (cwt refused it);
#  - --terms with --objective (the preset was dropped), an empty --terms
#    (it meant "full"), a repeated --start (the last won), --start without
#    '=' (the message named --set);
#  - library field names in messages: --penalty, --modes.
# Usage: bash tests/cli/wavelet_term_options.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
cd "$out"
cp "$root/examples/beam.toml" case.toml
cp "$root/examples/measured_knl50_T1.0.csv" data.csv
sums() { md5sum case.toml data.csv; }
before=$(sums)
identify=(identify case.toml -m data.csv --start knl=25 --max-evaluations 3)
landscape=(landscape case.toml -m data.csv --param knl --range 40:60:3)

refused() {
  local needle="$1"
  shift
  cli_refused "$*" "^podid: error: $needle" "$@"
}

# Only the IF term reads them.
refused "--fmin: expected an objective with the wavelet (IF) term" \
  "${identify[@]}" --objective full --fmin 20
refused "--penalty: expected an objective with the wavelet (IF) term" \
  "${identify[@]}" --terms U,S --penalty 0.1
refused "--mode-band: expected an objective with the wavelet (IF) term" \
  "${identify[@]}" --objective time-free --modes 2 --mode-band 2=100:400
refused "--omega0: expected an objective with the wavelet (IF) term" \
  "${identify[@]}" --objective full --omega0 7
refused "--ridge-snr: expected an objective with the wavelet (IF) term" \
  "${landscape[@]}" --objective full,time-free --ridge-snr 5
# The other family's parameter.
refused "--omega0: expected --wavelet morlet with it" \
  "${identify[@]}" --objective wavelet --wavelet morse --omega0 7
refused "--gamma: expected --wavelet morse with it" \
  "${identify[@]}" --objective wavelet --gamma 4
refused "--beta: expected --wavelet morse with it" \
  cwt data.csv --channel w1 --beta 30
# One frequency of the ridge's 32-voice grid.
refused "--fmin/--fmax: expected a band of at least 2 frequencies" \
  "${identify[@]}" --objective wavelet --fmin 119.99 --fmax 120
refused "--mode-band 2: expected a band of at least 2 frequencies" \
  "${identify[@]}" --objective wavelet --modes 2 --mode-band 2=100:100.5
# Terms, presets and starts.
refused "--terms: expected a list of terms U, S, V, IF (e.g. U,S,IF), got an empty one" \
  "${identify[@]}" --terms ''
refused "--[a-z]* excludes --[a-z]*" "${identify[@]}" --terms U,S --objective wavelet
refused "--start: expected each parameter at most once, got knl twice" \
  "${identify[@]}" --start knl=30
refused "--start knl: expected key=value" "${identify[@]}" --start knl
# Messages in the options' names, not the library's fields.
refused "--penalty: " "${identify[@]}" --objective wavelet --penalty 1e300
refused "--modes: expected at most the number of sensors" "${identify[@]}" --modes 7
echo "wavelet term options: ok"
