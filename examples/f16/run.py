#!/usr/bin/env python3
"""The F-16 ground vibration test export read and decomposed with the podid
CLI (docs/real-data.md):

  run.py PODID F16_Data.mat OUTDIR [--figure PNG]

1. podid pod on Signal_0 (115 acceleration channels as the test system wrote
   them): the record's numerical rank tells how many channels are live.
2. podid pod on the live channels only (--channels): POMs, singular values.
3. podid cwt (Morlet, penalised ridge) of the live channels and of the shaker
   force (Signal_1): the instantaneous frequency follows the sine sweep.
Results in OUTDIR (pod_all.json, pod_live.json, ridges_live.csv,
ridge_force.csv, summary.json). Needs NumPy; matplotlib and SciPy for --figure.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

# The two live channels of Signal_0 (the other 113 are all zero: step 1
# finds rank 2) and the shaker force channel of Signal_1.
LIVE = ["70:RMIS MS:1004:+Z", "108:RMIS WS:1004:+Z"]
FORCE = "3:DP_RIGHT:+Z"
# The sweep runs from 15 Hz down to 2 Hz; 1-40 Hz brackets it with a margin.
BAND = ["--fmin", "1", "--fmax", "40", "--band-limited"]


def run(command):
    print("$", " ".join(f'"{c}"' if " " in c else c for c in command), flush=True)
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(done.stdout, end="", flush=True)
    if done.returncode != 0:
        sys.exit(f"run.py: {command[0]} {command[1]} failed with exit status {done.returncode}")
    return done.stdout


def ridge_stats(csv, prefix=""):
    """Median IF (Hz) inside the cone over 10 s slices of record time, from a cwt -o CSV."""
    with open(csv) as handle:
        header = handle.readline().rstrip("\n").split(",")
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    t = table[:, header.index("t")]
    f = table[:, header.index(prefix + "f_Hz")]
    inside = table[:, header.index(prefix + "inside_coi")] > 0.5
    slices = {}
    for start in range(0, int(t[-1]) - 9, 10):
        keep = inside & (t >= start) & (t < start + 10)
        if keep.any():
            slices[f"{start}-{start + 10}"] = float(np.median(f[keep]))
    return t, f, inside, slices


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("podid")
    parser.add_argument("data", help="F16_Data.mat")
    parser.add_argument("out_dir")
    parser.add_argument("--figure", help="time histories and ridges, PNG")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    out = lambda name: os.path.join(args.out_dir, name)
    podid, data = args.podid, args.data

    run([podid, "pod", data, "--variable", "Signal_0", "--modes", "3", "--json", out("pod_all.json")])
    run([podid, "pod", data, "--variable", "Signal_0", "--channels", ",".join(LIVE),
         "--json", out("pod_live.json")])
    run([podid, "cwt", data, "--variable", "Signal_0", "--channels", ",".join(LIVE),
         "--channel", "all"] + BAND + ["-o", out("ridges_live.csv")])
    run([podid, "cwt", data, "--variable", "Signal_1", "--channel", FORCE] + BAND +
        ["-o", out("ridge_force.csv")])

    with open(out("pod_all.json")) as f:
        pod_all = json.load(f)
    with open(out("pod_live.json")) as f:
        pod_live = json.load(f)
    summary = {
        "all_channels": {"sensors": pod_all["sensors"], "numerical_rank": pod_all["numerical_rank"]},
        "live": {k: pod_live[k] for k in ("channels", "samples", "step_s", "start_s", "singular_values",
                                          "energy_fraction", "poms", "units")},
        "median_if_Hz": {},
    }
    ridges = {}
    for name in LIVE:
        ridges[name] = ridge_stats(out("ridges_live.csv"), name + "_")
        summary["median_if_Hz"][name] = ridges[name][3]
    ridges[FORCE] = ridge_stats(out("ridge_force.csv"))
    summary["median_if_Hz"][FORCE] = ridges[FORCE][3]
    with open(out("summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print(f"live channels: rank {pod_all['numerical_rank']} of {pod_all['sensors']}; "
          f"POM 1 holds {100 * pod_live['energy_fraction'][0]:.2f} % of the energy")

    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import scipy.io
        mat = scipy.io.loadmat(data)
        values = mat["Signal_0"][0, 0]["y_values"][0, 0]["values"]
        names = [str(n[0]) for n in mat["Signal_0"][0, 0]["function_record"][0, 0]["name"].ravel()]
        t0 = pod_live["start_s"]
        t = t0 + pod_live["step_s"] * np.arange(values.shape[0])
        fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
        for name in LIVE:
            axes[0].plot(t, values[:, names.index(name)], lw=0.3, label=name)
        axes[0].set_ylabel("acceleration (m/s^2)")
        axes[0].legend(loc="upper right")
        for name, (tr, f, inside, _) in ridges.items():
            axes[1].plot(tr[inside], f[inside], ".", ms=1, label=f"IF of {name}")  # record time
        axes[1].set_ylabel("ridge IF (Hz)")
        axes[1].set_xlabel("t (s)")
        axes[1].set_ylim(0, 20)
        axes[1].legend(loc="upper right", markerscale=8)
        fig.suptitle("F-16 GVT sine sweep: live channels and Morlet ridges (podid cwt)")
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print("figure ->", args.figure)


if __name__ == "__main__":
    main()
