#!/usr/bin/env bash
# Plots under hostile input (issue 10 items 1, 2): no user text reaches a
# gnuplot script unescaped, and plot temporaries never follow a planted
# symlink. Names with a backquote or '@' in a case file's parameter (one with
# a newline or a quote is refused there), and with a newline, quotes, a
# backquote or '@' in a data file's channel and a --plot path, run nothing
# (the files X* they would create do not exist) and still give a PNG; the old
# predictable temporaries (<png>.tmp<PID>.data0, .gp) are not touched; the
# private folder in $TMPDIR is gone afterwards.
# Usage: bash tests/cli/hostile_plot.sh PODID (from the repo root).
set -u
podid="$(realpath "$1")"
root="$PWD"
. tests/support/cli.sh
cli_scratch
if ! command -v gnuplot >/dev/null && [ -z "${PODID_GNUPLOT:-}" ]; then
  echo "hostile plot: skipped (no gnuplot)"
  exit 0
fi
gnuplot_program=$(realpath "${PODID_GNUPLOT:-$(command -v gnuplot)}")
cd "$out"
mkdir tmp
export TMPDIR="$out/tmp"
# Each evil text tries a gnuplot command (system), a backquote command
# substitution and a macro, after a newline that would end the string. A
# case's names take no newline or quote (refused at the case, below), so the
# parameter name keeps the backquote and the macro.
name='knl `touch XB` @x'
sed "s/^name = \"knl\"/name = \"$name\"/" "$root/examples/beam.toml" >evil.toml
grep -q 'touch XB' evil.toml || fail "could not write the evil case"
toml_name='knl\\nsystem \\"touch XA\\"\\nprint `touch XB` @x'  # sed: \\ is one \
sed "s/^name = \"knl\"/name = \"$toml_name\"/" "$root/examples/beam.toml" >evil_nl.toml
grep -q 'touch XA' evil_nl.toml || fail "could not write the evil case with newlines"
data="$root/tests/data/measured_knl50_T0.1.csv"
png='p
system "touch XC"
`touch XD`.png'
check_nothing_ran() {
  ls X* >/dev/null 2>&1 && fail "$1: a command ran: $(ls X*)"
  [ -z "$(ls -A tmp)" ] || fail "$1: left in TMPDIR: $(ls -A tmp)"
  ls -A | grep -q '\.tmp' && fail "$1: temporary left: $(ls -A | grep '\.tmp')"
  return 0
}
is_png() { head -c 8 "$1" | od -An -tx1 | tr -d ' \n' | grep -q '^89504e470d0a1a0a$'; }

# A parameter name with newlines and quotes is refused at the case (exit 1).
"$podid" landscape evil_nl.toml -m "$data" --param knl --range 0:100:3 \
  --objective time-free --plot refused.png >stdout 2>stderr
[ $? -eq 1 ] || fail "a name with newlines: expected exit 1"
grep -q "identify.parameter.0.name: expected a name of at most 256 bytes without control" stderr \
  || fail "a name with newlines: $(cat stderr)"
[ ! -e refused.png ] || fail "a name with newlines: a plot was written"
check_nothing_ran refused

# landscape --plot: the parameter name is the x label; the path has a newline.
"$podid" landscape evil.toml -m "$data" --param "$name" --range 0:100:3 \
  --objective time-free --plot "$png" >stdout 2>stderr || fail "landscape: $(cat stderr)"
check_nothing_ran landscape
is_png "$png" || fail "landscape: no PNG at the path with a newline"

# identify --plot-dir: the parameter name is in the titles.
"$podid" identify evil.toml -m "$data" --objective time-free --max-evaluations 3 \
  --plot-dir figs >stdout 2>stderr || fail "identify: $(cat stderr)"
check_nothing_ran identify
for f in fig2a_start fig2b_optimum convergence; do
  is_png "figs/$f.png" || fail "identify: no figs/$f.png"
done

# cwt --plot: the channel name (a CSV header cell) is in the title.
sed '1s/w6/w`touch XE`@x"q/' "$data" >evil.csv
"$podid" cwt evil.csv --channel 'w`touch XE`@x"q' --plot cwt.png >stdout 2>stderr \
  || fail "cwt: $(cat stderr)"
check_nothing_ran cwt
is_png cwt.png || fail "cwt: no PNG"

# Planted symlinks at the names the plot temporaries used to have: with the
# PID known in advance (exec keeps it), they point at a victim file.
printf 'precious\n' >victim
bash -c 'for s in data0 data1 data2 gp png; do ln -s victim "planted.png.tmp$$.$s"; done
         exec "$0" cwt "$1" --channel w6 --plot planted.png' "$podid" "$data" >stdout 2>stderr \
  || fail "cwt with planted links: $(cat stderr)"
[ "$(cat victim)" = precious ] || fail "a planted symlink was followed: victim overwritten"
is_png planted.png || fail "planted: no PNG"
[ "$(find . -maxdepth 1 -name 'planted.png.tmp*' -type l | wc -l)" -eq 5 ] \
  || fail "planted links changed"
rm planted.png.tmp*
check_nothing_ran planted

# A relative gnuplot path still works although gnuplot runs in the private
# folder (it is made absolute before the chdir).
mkdir bin
ln -s "$gnuplot_program" bin/gnuplot
PODID_GNUPLOT=bin/gnuplot "$podid" cwt "$data" --channel w6 --plot rel.png >stdout 2>stderr \
  || fail "relative PODID_GNUPLOT: $(cat stderr)"
is_png rel.png || fail "relative PODID_GNUPLOT: no PNG"
check_nothing_ran "relative gnuplot"

# Without gnuplot the script is kept next to the PNG: its paths are escaped
# too, so running it later runs nothing either.
PODID_GNUPLOT=/nonexistent "$podid" landscape evil.toml -m "$data" --param "$name" \
  --range 0:100:3 --objective time-free --plot "$png.kept" >stdout 2>stderr \
  || fail "landscape without gnuplot: $(cat stderr)"
kept=$(ls -d "$png.kept".gnuplot-*/)
[ -f "${kept}plot.gp" ] || fail "no kept script"
"$gnuplot_program" "${kept}plot.gp" 2>gnuplot.err || fail "the kept script fails: $(cat gnuplot.err)"
check_nothing_ran "kept script"
is_png "$png.kept" || fail "the kept script drew no PNG"
# A gnuplot that fails leaves none of the command's outputs and replaces
# nothing: every file is staged and published only once the plot is drawn
# (before, -o and --json were written first and stayed behind).
printf '#!/bin/sh\nexit 1\n' >bin/failing
chmod +x bin/failing
printf 'old\n' >old.csv
printf '{"old": 1}\n' >old.json
expect_no_outputs() {  # $1: what, then the files that must not exist
  local what=$1
  shift
  [ "$(cat old.csv)" = old ] || fail "$what: old.csv was replaced"
  [ "$(cat old.json)" = '{"old": 1}' ] || fail "$what: old.json was replaced"
  for f in "$@"; do [ ! -e "$f" ] || fail "$what: $f was left behind"; done
  grep -q ' -> \|written to' stdout && fail "$what: announced a file: $(cat stdout)"
  check_nothing_ran "$what"
}
PODID_GNUPLOT=bin/failing "$podid" cwt "$data" --channel w6 -o old.csv --scalogram sg.csv \
  --plot fail.png >stdout 2>stderr
[ $? -eq 1 ] || fail "cwt with a failing gnuplot: expected exit 1"
grep -q "gnuplot (.*) failed drawing fail.png: exit status 1$" stderr \
  || fail "cwt, failing gnuplot: $(cat stderr)"
expect_no_outputs "cwt, failing gnuplot" sg.csv fail.png
PODID_GNUPLOT=bin/failing "$podid" landscape evil.toml -m "$data" --param "$name" \
  --range 0:100:3 --objective time-free -o old.csv --json old.json --plot fail.png >stdout 2>stderr
[ $? -eq 1 ] || fail "landscape with a failing gnuplot: expected exit 1"
expect_no_outputs "landscape, failing gnuplot" fail.png
PODID_GNUPLOT=bin/failing "$podid" identify evil.toml -m "$data" --objective time-free \
  --max-evaluations 3 --json old.json --plot-dir new/figs >stdout 2>stderr
[ $? -eq 1 ] || fail "identify with a failing gnuplot: expected exit 1"
expect_no_outputs "identify, failing gnuplot" new

# gnuplot's own messages never reach the terminal raw: its stdout and stderr
# go to a file in the private folder. After a success its informative lines
# are relayed as notes naming the PNG (no blank lines, no echoed script line
# or caret, no "plot.gp" line N:, control bytes escaped, at most 5 and a
# count); after a failure the error says why.
esc=$(printf '\033')
cat >bin/chatty <<EOF
#!/bin/sh
printf '\n  plot "data0" title "ECHOED"\n                        ^\n'
printf '"plot.gp" line 3: warning: odd label \033[31mred\n' >&2
for i in 1 2 3 4 5 6; do echo "warning: more \$i"; done
printf 'Warning: empty y range [0:0], adjusting to [-1:1]\n' >&2
exec "$gnuplot_program" "\$@"
EOF
chmod +x bin/chatty
PODID_GNUPLOT=bin/chatty "$podid" cwt "$data" --channel w6 --plot warn.png >stdout 2>stderr \
  || fail "chatty gnuplot: $(cat stderr)"
is_png warn.png || fail "chatty gnuplot: no PNG"
grep -qx 'podid: note: gnuplot, warn.png: warning: odd label \\x1b\[31mred' stderr \
  || fail "chatty gnuplot: no escaped warning: $(cat stderr)"
grep -qx 'podid: note: gnuplot, warn.png: warning: more 4' stderr \
  || fail "chatty gnuplot: no relayed line: $(cat stderr)"
grep -qx 'podid: note: gnuplot, warn.png: ([0-9]* more)' stderr \
  || fail "chatty gnuplot: no count of the lines left: $(cat stderr)"
[ "$(grep -c '^podid: note: gnuplot, warn.png: ' stderr)" -eq 6 ] \
  || fail "chatty gnuplot: not 5 lines and a count: $(cat stderr)"
grep -v '^podid: ' stderr && fail "chatty gnuplot: a raw line on stderr"
grep -q 'ECHOED\|\^\|plot\.gp\|more 6\|adjusting' stderr stdout \
  && fail "chatty gnuplot: a line that should not show: $(cat stderr stdout)"
grep -q "$esc" stderr stdout && fail "chatty gnuplot: a raw escape byte"
check_nothing_ran "chatty gnuplot"

cat >bin/broken <<'EOF'
#!/bin/sh
echo
printf '"plot.gp" line 9: cannot open font sans (fake)\n' >&2
exit 1
EOF
chmod +x bin/broken
PODID_GNUPLOT=bin/broken "$podid" cwt "$data" --channel w6 --plot broken.png >stdout 2>stderr
[ $? -eq 1 ] || fail "broken gnuplot: expected exit 1"
grep -qx 'podid: error: plot: gnuplot (bin/broken) failed drawing broken.png: cannot open font sans (fake)' \
  stderr || fail "broken gnuplot: $(cat stderr)"
grep -v '^podid: ' stderr && fail "broken gnuplot: a raw line on stderr"
[ ! -e broken.png ] || fail "broken gnuplot: a PNG was written"
check_nothing_ran "broken gnuplot"
echo "hostile plot: ok"
