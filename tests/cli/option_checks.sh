#!/usr/bin/env bash
# Command-line options refused before anything is computed, the message
# naming the option typed (exit 1, one line, nothing on stdout, no file):
#  - --terms with a repeated term (its later weight silently won);
#  - --weights above 1e12 (1e308 made F overflow: exit 0 with "start nan");
#  - landscape --objective with a repeated or empty preset (a repeated one
#    gave two CSV columns of one name and one JSON key), and --param2 equal
#    to --param;
#  - --channels '' (taken for none given), --channels w1,w1, and --decimate
#    in identify (the case file was blamed for it).
# Usage: bash tests/cli/option_checks.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
cd "$out" || exit 1
data="$root/tests/data/measured_knl50_T0.1.csv"
cp "$root/examples/beam.toml" case.toml
sums() { md5sum case.toml; }
before=$(sums)

# refused NEEDLE COMMAND...: exit 1, one line starting with NEEDLE, nothing
# computed, no output file written.
refused() {
  local needle="$1"
  shift
  cli_refused "$*" "^podid: error: $needle" "$@"
  if [ -e ff.csv ] || [ -e ff.json ]; then fail "$*: wrote an output file"; fi
  return 0
}

ident=(identify case.toml -m "$data" --start knl=25 --max-evaluations 2 --json ff.json)
refused "--terms: expected each term once, got U twice" "${ident[@]}" --terms U,U --weights 1,5
refused "--terms: expected each term once, got S twice" "${ident[@]}" --terms S,IF,S
refused '--weights: expected weights of at most 1e+12, got "1e308"' \
  "${ident[@]}" --terms U,S,IF --weights 1e308,1e308,1e308
refused '--weights: expected weights of at most 1e+12, got "2e12"' \
  "${ident[@]}" --terms U,S --weights 1,2e12
refused '--channels: expected a list of channel names, got ""' "${ident[@]}" --channels ''
refused '--channels: expected distinct channel names, got "w1" twice' \
  "${ident[@]}" --channels w1,w1
refused '--channels: expected non-empty channel names' "${ident[@]}" --channels w1,,w2
refused "--decimate: expected 1 for identify and landscape" "${ident[@]}" --decimate 10
refused '--channels: expected a list of channel names, got ""' pod "$data" --channels '' \
  --json ff.json

land=(landscape case.toml -m "$data" --param knl --range 40:60:3 -o ff.csv --json ff.json)
refused "--objective: expected each objective once, got full twice" \
  "${land[@]}" --objective full,full
refused "--objective: expected each objective once, got time-free twice" \
  "${land[@]}" --objective time-free,full,time-free
refused '--objective: expected a list of full, time-free, wavelet, got ""' \
  "${land[@]}" --objective full,,wavelet
refused '--objective: expected a list of full, time-free, wavelet, got ""' \
  "${land[@]}" --objective full,
refused '--objective: expected a list of full, time-free, wavelet, got "fast"' \
  "${land[@]}" --objective fast
refused '--param2: expected a parameter other than --param'"'"'s, got "knl"' \
  "${land[@]}" --param2 knl --range2 40:60:3
refused "--decimate: expected 1 for identify and landscape" "${land[@]}" --decimate 2

# What stays accepted: the largest weight, distinct presets (one column each).
"$podid" "${ident[@]}" --terms U,S --weights 1,1e12 >stdout 2>stderr ||
  fail "--weights 1,1e12: exit $? ($(cat stderr))"
grep -q '1e+12 dS' stdout || fail "--weights 1,1e12: $(cat stdout)"
rm -f ff.json
"$podid" "${land[@]}" --objective time-free,full >stdout 2>stderr ||
  fail "--objective time-free,full: exit $? ($(cat stderr))"
[ "$(head -1 ff.csv)" = knl,time-free,full ] || fail "CSV header: $(head -1 ff.csv)"
echo "option checks OK"
