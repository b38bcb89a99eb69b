#!/usr/bin/env python3
"""The README's identification from Python: knl of the reference beam from the
1 s measured record with the wavelet objective, starting from knl = 25, then
the three objectives' landscape over knl = 0..200, plotted with matplotlib.

    PYTHONPATH=build/default/python python3 python/examples/identify_readme.py [OUT.png]
"""
import pathlib
import sys

import podid

root = pathlib.Path(__file__).resolve().parents[2]
case = str(root / "examples" / "beam.toml")
measured = str(root / "examples" / "measured_knl50_T1.0.csv")

result = podid.identify(case, measured, objective="wavelet", start={"knl": 25.0})
print(result["brief"])
if not result["usable"]:
    sys.exit(2)


def bar(done, total):
    print(f"\rlandscape: {done}/{total} points", end="", file=sys.stderr, flush=True)


tty = sys.stderr.isatty()
grid = podid.landscape(case, measured, "knl", 0.0, 200.0, 201, progress=bar if tty else None)
if tty:
    print(file=sys.stderr)
for name, m in grid["metrics"].items():
    print(f"{name:10s} minima {m['local_minima']}, minimiser {m['global_minimiser']:g}, "
          f"basin {m['basin'][0]:g}..{m['basin'][1]:g}")

if len(sys.argv) > 1:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for name, values in grid["values"].items():
        ax.semilogy(grid["x"], values, label=name)
    ax.axvline(result["parameters"]["knl"], color="k", lw=0.8, ls="--", label="identified knl")
    ax.set_xlabel("knl")
    ax.set_ylabel("objective F")
    ax.legend()
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=100)
    print("plot written to", sys.argv[1])
