#!/usr/bin/env bash
# Regenerates the paper's figures 2-6 (Lenaerts, Kerschen & Golinval) with
# podid into docs/figures/, with the landscape metrics and identification
# results as CSV/JSON next to them. See docs/reproduction.md.
#
# Usage: bash docs/reproduce.sh          (from anywhere; ~1-2 min on 2 cores)
#   PODID=/path/to/podid bash docs/reproduce.sh   uses that binary; otherwise
#   build/release/apps/podid, built with the release preset if missing.
# Needs gnuplot (scripts/install-deps.sh installs gnuplot-nox) and python3.
set -euo pipefail
cd "$(dirname "$0")/.."
start_time=$(date +%s)

podid="${PODID:-build/release/apps/podid}"
if [[ ! -x "$podid" ]]; then
  echo "== building podid (release preset)"
  cmake --preset release >/dev/null
  cmake --build --preset release --target podid_cli -j "$(nproc)"
fi
command -v gnuplot >/dev/null || { echo "reproduce.sh: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }

fig=docs/figures
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$fig"
case_file=examples/beam.toml
grid=0:200:801   # knl from 0 to 200 in steps of 0.25

# Records. 0.1 s and 1.0 s are the independent reference data (DOP853, 1 %
# noise, see /work/shared/reference/README.md). 0.02 s and 0.2 s are the first
# 101 and 1001 samples of the 1.0 s record (same data, truncated).
cp examples/measured_knl50_T0.1.csv "$work/T0.1.csv"
cp examples/measured_knl50_T1.0.csv "$work/T1.0.csv"
head -n 102 examples/measured_knl50_T1.0.csv >"$work/T0.02.csv"
head -n 1002 examples/measured_knl50_T1.0.csv >"$work/T0.2.csv"

# ---------------------------------------------------------------- fig. 2
# 0.1 s record, full objective (eq. 19) on the first POM, start at 80 % of
# the true value (knl = 40), as in the paper's section 4.2.
echo "== fig. 2: identify from knl = 40 on the 0.1 s record (full objective)"
"$podid" identify "$case_file" --measured "$work/T0.1.csv" --objective full --start knl=40 \
  --json "$fig/fig2_identify.json" --plot-dir "$work/fig2" 2>/dev/null
cp "$work/fig2/fig2a_start.png" "$fig/fig2a_start.png"
cp "$work/fig2/fig2b_optimum.png" "$fig/fig2b_optimum.png"

# ---------------------------------------------------------------- landscapes
# One run per record; every objective shares each grid point's simulation.
# The wavelet objective needs a record longer than its cone of influence at
# the lowest ridge frequency: 0.02 s cannot hold one (it is shorter than one
# period of the first mode), 0.2 s needs --fmin 20 (the default 10 Hz needs
# 0.27 s); the first mode's IF is 33-40 Hz, inside both bands.
echo "== figs. 3-6: landscapes over knl = 0..200 (801 points)"
landscape() {  # name record objectives [extra options]
  local name=$1 record=$2 objectives=$3
  shift 3
  "$podid" landscape "$case_file" --measured "$record" --param knl --range "$grid" \
    --objective "$objectives" "$@" -o "$fig/landscape_$name.csv" --json "$fig/landscape_$name.json" \
    2>/dev/null | tee "$work/landscape_$name.txt"
}
landscape T0.02 "$work/T0.02.csv" full,time-free
landscape T0.1 "$work/T0.1.csv" full,time-free
landscape T0.2 "$work/T0.2.csv" full,time-free,wavelet --fmin 20
landscape T1.0 "$work/T1.0.csv" full,time-free,wavelet --plot "$fig/landscape_T1.0.png"

# ---------------------------------------------------------------- identification starts
# Starts {5, 10, 25, 100, 150, 200} with the full and wavelet objectives on
# the 1 s record, and the full objective on the 0.1 s record (plus 40).
echo "== identification from several starts"
jobs_file="$work/jobs"
: >"$jobs_file"
for s in 5 10 25 100 150 200; do
  for o in full wavelet; do echo "T1.0 $o $s" >>"$jobs_file"; done
done
for s in 5 10 25 40 100 150 200; do echo "T0.1 full $s" >>"$jobs_file"; done
export podid case_file work
xargs -P 2 -L 1 bash -c '"$podid" identify "$case_file" --measured "$work/$0.csv" --objective "$1" \
  --start knl="$2" --json "$work/identify_$0_$1_$2.json" >/dev/null 2>&1 || true' <"$jobs_file"

# ---------------------------------------------------------------- tables
python3 - "$fig" "$work" <<'EOF'
import csv, json, sys, os
fig, work = sys.argv[1], sys.argv[2]
rows = []
for record in ["T0.02", "T0.1", "T0.2", "T1.0"]:
    j = json.load(open(f"{fig}/landscape_{record}.json"))
    for name, m in j["objectives"].items():
        rows.append([record[1:] + " s", name, m["local_minima"], m["global_minimiser"],
                     "%g..%g" % tuple(m["basin"]), "%.1f" % (100 * m["basin_fraction"]),
                     "%.3f" % m["roughness"], "%.4g" % m["global_minimum"]])
with open(f"{fig}/landscape_metrics.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["record", "objective", "local_minima", "global_minimiser", "basin",
                "basin_percent", "roughness", "global_minimum"])
    w.writerows(rows)
ident = []
for line in open(f"{work}/jobs"):
    record, objective, start = line.split()
    path = f"{work}/identify_{record}_{objective}_{start}.json"
    if not os.path.exists(path):
        ident.append([record[1:] + " s", objective, start, "", "", "", "no result"])
        continue
    j = json.load(open(path))
    ident.append([record[1:] + " s", objective, start, "%.4f" % j["parameters"]["knl"],
                  "%.4g" % j["objective"], j["evaluations"], j["termination"]])
with open(f"{fig}/identify_starts.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["record", "objective", "start", "knl", "F", "evaluations", "termination"])
    w.writerows(ident)
print("\nlandscape metrics (docs/figures/landscape_metrics.csv)")
for r in rows: print("  %-7s %-10s minima %4s  minimiser %7s  basin %-13s (%5s %%)  roughness %8s" % tuple(r[:7]))
print("\nidentification (docs/figures/identify_starts.csv)")
for r in ident: print("  %-6s %-8s start %4s -> knl %9s  F %10s  %3s evaluations  %s" % tuple(r))
EOF

# ---------------------------------------------------------------- figures
echo "== plotting"
gp() { gnuplot -e "set terminal pngcairo size 1000,420 noenhanced font 'sans,10'; set datafile separator ','; \
  set grid; set key top right; set format y '%g'; set xlabel 'knl (k3 / 1e8 N/m^3)'; $1"; }
# CSV columns: 1 knl, then the objectives in the order given to landscape.
gp "set output '$fig/fig3_full_T0.02_T0.2.png'; set multiplot layout 1,2;
  set title 'full objective (dU + dS + dV), 0.02 s record'; set ylabel 'F'; set logscale y;
  plot '$fig/landscape_T0.02.csv' using 1:2 every ::1 with lines lw 1.5 title 'full';
  set title 'full objective (dU + dS + dV), 0.2 s record';
  plot '$fig/landscape_T0.2.csv' using 1:2 every ::1 with lines lw 1.5 title 'full'; unset multiplot"
gp "set output '$fig/fig4_time_free.png'; set key bottom right; set title 'time-free objective (dU + dS)'; set ylabel 'F'; set logscale y;
  plot '$fig/landscape_T0.02.csv' using 1:3 every ::1 with lines lw 1.5 title '0.02 s',
       '$fig/landscape_T0.2.csv' using 1:3 every ::1 with lines lw 1.5 title '0.2 s',
       '$fig/landscape_T1.0.csv' using 1:3 every ::1 with lines lw 1.5 title '1 s'"
gp "set output '$fig/fig5_wavelet_vs_full_T1.0.png'; set multiplot layout 1,2;
  set title 'without wavelet: full (dU + dS + dV), 1 s'; set ylabel 'F'; set logscale y;
  plot '$fig/landscape_T1.0.csv' using 1:2 every ::1 with lines lw 1.5 title 'full';
  set title 'with wavelet: dU + dS + dIF, 1 s';
  plot '$fig/landscape_T1.0.csv' using 1:4 every ::1 with lines lw 1.5 lc 3 title 'wavelet'; unset multiplot"
gp "set output '$fig/fig6_zoom_T1.0.png'; set multiplot layout 1,2; set xrange [0:40];
  set title 'zoom: full (dU + dS + dV), 1 s, knl 0..40'; set ylabel 'F';
  plot '$fig/landscape_T1.0.csv' using 1:2 every ::1 with lines lw 1.5 title 'full';
  set title 'zoom: wavelet (dU + dS + dIF), 1 s, knl 0..40';
  plot '$fig/landscape_T1.0.csv' using 1:4 every ::1 with lines lw 1.5 lc 3 title 'wavelet'; unset multiplot"

elapsed=$(( $(date +%s) - start_time ))
echo
echo "reproduce.sh: figures and tables in $fig/ (${elapsed} s)"
ls "$fig"
