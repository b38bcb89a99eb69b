#!/usr/bin/env python3
"""The Silverbox as a one-dof Duffing oscillator, from the raw file to the
validation RMS (docs/real-data.md).

  run.py PODID SNLS80mV.mat OUTDIR [--figure PNG] [--max-evaluations N]

1. podid identify silverbox.toml on the multisine part (samples 40,496 to
   127,412, the case's [data] window), the Duffing model (k, d, k3, gain,
   offset) and the linear one (k3 = 0), objective dS + dV (one channel: the
   record's norm and its normalised time history, i.e. output error).
2. podid simulate each fitted model from rest on samples 0 to 40,495 (the
   growing-amplitude part the fit never saw) with the measured V1 as input.
3. The RMS of simulated - measured V2 there, with V2 read by scipy.io.loadmat
   (not by podid), into OUTDIR/summary.json, and a measured-vs-simulated plot.
Needs NumPy and SciPy (Debian's /usr/bin/python3); matplotlib for --figure.
"""
import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np
import scipy.io

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, "silverbox.toml")
RATE_HZ = 1e7 / 2**14            # the benchmark's sampling rate (no time vector in the file)
VALIDATION = (0, 40495)          # 0-based inclusive: the growing-amplitude part
FIT = (40496, 127412)            # the multisine part (the case's data.window)


def run(command):
    print("$", " ".join(command), flush=True)
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(done.stdout, end="", flush=True)
    if done.returncode != 0:
        sys.exit(f"run.py: {command[0]} {command[1]} failed with exit status {done.returncode}")
    return done.stdout


def linear_case(out_dir):
    """silverbox.toml without the k3 parameter (k3 stays 0), its paths made absolute."""
    text = open(CASE).read()
    blocks = text.split("[[identify.parameter]]")
    kept = [b for b in blocks[1:] if not re.search(r'key\s*=\s*"nonlinearity\.0\.k3"', b)]
    assert len(kept) == len(blocks) - 2, "silverbox.toml: expected one k3 parameter"
    text = "[[identify.parameter]]".join([blocks[0]] + kept)
    text = re.sub(r'"(\w+\.mtx)"', lambda m: '"' + os.path.join(HERE, m.group(1)) + '"', text)
    path = os.path.join(out_dir, "silverbox_linear.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def identify(podid, case, data, out_json, max_evaluations):
    run([podid, "identify", case, "-m", data, "--terms", "S,V", "--keep-mean",
         "--max-evaluations", str(max_evaluations), "--json", out_json])
    with open(out_json) as f:
        return json.load(f)


def case_sets(case, result):
    """--set key=value for each identified parameter (value x scale)."""
    text = open(case).read()
    sets = []
    for block in text.split("[[identify.parameter]]")[1:]:
        name = re.search(r'name\s*=\s*"([^"]+)"', block).group(1)
        key = re.search(r'key\s*=\s*"([^"]+)"', block).group(1)
        scale = float(re.search(r"scale\s*=\s*([-+0-9.eE]+)", block).group(1))
        sets += ["--set", f"{key}={result['parameters'][name] * scale!r}"]
    return sets


def simulate(podid, case, data, result, first, last, out_csv):
    """The fitted model from rest over samples first..last, read back."""
    step = 1.0 / RATE_HZ
    run([podid, "simulate", case, "--no-noise", "--set", f'data.file="{data}"',
         "--set", f"time.start={first * step!r}", "--set", f"time.duration={(last - first) * step!r}",
         "--set", f"time.step={step!r}"] + case_sets(case, result) + ["-o", out_csv])
    simulated = np.loadtxt(out_csv, delimiter=",", skiprows=1)
    assert simulated.shape[0] == last - first + 1, out_csv
    return simulated[:, 1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("podid")
    parser.add_argument("data", help="SNLS80mV.mat")
    parser.add_argument("out_dir")
    parser.add_argument("--figure", help="measured-vs-simulated PNG")
    parser.add_argument("--max-evaluations", type=int, default=1000)
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    data = os.path.abspath(args.data)
    mat = scipy.io.loadmat(data)
    v2 = mat["V2"].ravel()
    measured = v2[VALIDATION[0]:VALIDATION[1] + 1]

    summary = {"rate_Hz": RATE_HZ, "validation_samples": list(VALIDATION), "fit_samples": list(FIT)}
    simulated = {}
    for label, case in (("duffing", CASE), ("linear", linear_case(args.out_dir))):
        result = identify(args.podid, case, data, os.path.join(args.out_dir, f"identify_{label}.json"),
                          args.max_evaluations)
        if not result["usable"]:
            sys.exit(f"run.py: the {label} fit is not usable: {result['message']}")
        sim = simulate(args.podid, case, data, result, *VALIDATION,
                       os.path.join(args.out_dir, f"validation_{label}.csv"))
        simulated[label] = sim
        rms_V = float(np.sqrt(np.mean((sim - measured) ** 2)))
        unc = result.get("uncertainty", {}).get("parameters", {})
        summary[label] = {
            "parameters": result["parameters"],
            "intervals_95": {name: [u["lower"], u["upper"]] for name, u in unc.items()},
            "objective": result["objective"], "evaluations": result["evaluations"],
            "termination": result["termination"], "validation_rms_mV": 1e3 * rms_V}
        print(f"{label}: validation RMS {1e3 * rms_V:.4f} mV (samples {VALIDATION[0]}..{VALIDATION[1]})")
    with open(os.path.join(args.out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)

    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        t = np.arange(VALIDATION[0], VALIDATION[1] + 1) / RATE_HZ
        fig, axes = plt.subplots(3, 1, figsize=(9, 8))
        axes[0].plot(t, measured, lw=0.4, color="k", label="measured V2")
        axes[0].plot(t, simulated["duffing"], lw=0.4, color="tab:red", alpha=0.7,
                     label="simulated (Duffing)")
        axes[0].set_ylabel("V2 (V)")
        axes[0].legend(loc="upper left")
        zoom = (t >= 60.0) & (t <= 60.25)  # the largest amplitudes, 0.25 s
        axes[1].plot(t[zoom], measured[zoom], "k.-", lw=0.8, ms=3, label="measured V2")
        for label, color in (("linear", "tab:blue"), ("duffing", "tab:red")):
            axes[1].plot(t[zoom], simulated[label][zoom], lw=0.8, color=color, label=f"simulated ({label})")
        axes[1].set_ylabel("V2 (V)")
        axes[1].legend(loc="upper left", fontsize=8)
        for label, color in (("linear", "tab:blue"), ("duffing", "tab:red")):
            axes[2].plot(t, 1e3 * (simulated[label] - measured), lw=0.3, color=color,
                         label=f"{label}: RMS {summary[label]['validation_rms_mV']:.2f} mV")
        axes[2].set_ylabel("simulated - measured (mV)")
        axes[2].set_ylim(-20, 20)
        axes[2].set_xlabel("t (s)")
        axes[2].legend(loc="upper left")
        fig.suptitle("Silverbox, validation on samples 0-40,495 (fit on 40,496-127,412)")
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print("figure ->", args.figure)


if __name__ == "__main__":
    main()
