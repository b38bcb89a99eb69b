#!/usr/bin/python3
"""Worst-case IF error at the cone-of-influence border, over end phases.

Usage: /usr/bin/python3 scripts/wavelet_border_errors.py PODID [--phases 16]

For a 33 Hz tone, a linear chirp (20 -> 80 Hz) and a Duffing-like decay
(amplitude exp(-2 t), IF 33 + 6 exp(-4 t) Hz), each 1 s at 5 kHz with 16
starting phases (so the record ends at 16 different phases), runs
`podid cwt --channel all` (default 10-120 Hz grid, 32 voices, penalised
ridge, phase IF) with each padding and cone factor, and prints the worst
relative IF error inside the cone over all phases and samples, and the
worst error in the middle half of the record (the floor without border
effects). docs/wavelet.md quotes its output.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

FS_HZ = 5000.0
T = np.arange(5001) / FS_HZ


def signals(phases):
    phi = 2 * np.pi * np.arange(phases) / phases
    tone = [np.cos(2 * np.pi * 33 * T + p) for p in phi]
    chirp = [np.cos(2 * np.pi * (20 * T + 30 * T**2) + p) for p in phi]
    a = 2.0
    theta = 2 * np.pi * (33 * T + 6 * (1 - np.exp(-2 * a * T)) / (2 * a))
    decay = [np.exp(-a * T) * np.cos(theta + p) for p in phi]
    return {
        "33 Hz tone": (tone, lambda t: 33 + 0 * t),
        "chirp 20 -> 80 Hz": (chirp, lambda t: 20 + 60 * t),
        "decay 39 -> 33 Hz": (decay, lambda t: 33 + 6 * np.exp(-2 * a * t)),
    }


def run(podid, folder, name, channels, padding, coi):
    data = os.path.join(folder, "x.csv")
    header = "t," + ",".join(f"c{i}" for i in range(len(channels)))
    np.savetxt(data, np.column_stack([T] + channels), delimiter=",", header=header,
               comments="", fmt="%.15e")
    out = os.path.join(folder, "r.csv")
    subprocess.run([podid, "cwt", data, "--channel", "all", "--padding", padding,
                    "--coi-factor", str(coi), "-o", out], check=True, stdout=subprocess.DEVNULL)
    r = np.genfromtxt(out, delimiter=",", names=True)
    return r


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("podid")
    parser.add_argument("--phases", type=int, default=16)
    args = parser.parse_args()
    print("| signal | padding | worst, coi_factor 1 | worst, coi_factor 2 | middle half |")
    print("| --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as folder:
        for name, (channels, truth) in signals(args.phases).items():
            for padding in ("reflect", "zero", "periodic"):
                cells = []
                middle = 0.0
                for coi in (1, 2):
                    r = run(args.podid, folder, name, channels, padding, coi)
                    t = r["t"]
                    f_true = truth(t)
                    worst = 0.0
                    for i in range(len(channels)):
                        f = r[f"c{i}_f_Hz"]
                        inside = r[f"c{i}_inside_coi"] > 0.5
                        err = np.abs(f - f_true) / f_true
                        worst = max(worst, float(np.max(err[inside])) if inside.any() else np.nan)
                        mid = (t >= 0.25) & (t <= 0.75)
                        middle = max(middle, float(np.max(err[mid])))
                    cells.append(f"{worst:.2g}")
                print(f"| {name} | {padding} | {cells[0]} | {cells[1]} | {middle:.2g} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
