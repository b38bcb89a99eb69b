#!/usr/bin/env python3
"""Reference outputs of the conditioning chain (lib/src/conditioning.cpp) by
scipy.signal, on a fixed two-channel signal sampled at 1 kHz.

    python3 tests/data/conditioning/make_reference.py OUTPUT_DIR

writes input.csv and one CSV per case into OUTPUT_DIR.
tests/core/conditioning_test.cpp runs it into a temporary folder, conditions
input.csv with podid and compares with the other files.
"""
import os
import sys

import numpy as np
from scipy import signal

FS = 1000.0
N = 2000


def write(path, t, x, names):
    with open(path, "w") as f:
        f.write("t," + ",".join(names) + "\n")
        for i in range(len(t)):
            f.write("%.17g," % t[i] + ",".join("%.17g" % v for v in x[i]) + "\n")


def main():
    out = sys.argv[1]
    t = np.arange(N) / FS
    x1 = (np.sin(2 * np.pi * 7 * t) + 0.5 * np.sin(2 * np.pi * 60 * t + 0.3)
          + 0.2 * np.sin(2 * np.pi * 180 * t) + 0.3 + 0.5 * t)
    x2 = np.cos(2 * np.pi * 23 * t) * np.exp(-t) + 0.1 * np.sin(2 * np.pi * 300 * t) - 0.2 * t
    x = np.column_stack([x1, x2])
    names = ["a", "b"]
    write(os.path.join(out, "input.csv"), t, x, names)

    def sosfiltfilt(btype, order, wn_hz, data):
        sos = signal.butter(order, wn_hz, btype=btype, fs=FS, output="sos")
        return signal.sosfiltfilt(sos, data, axis=0)

    cases = {
        "lowpass4_40": sosfiltfilt("lowpass", 4, 40.0, x),
        "highpass3_15": sosfiltfilt("highpass", 3, 15.0, x),
        "bandpass4_20_100": sosfiltfilt("bandpass", 4, [20.0, 100.0], x),
        "bandpass16_40_90": sosfiltfilt("bandpass", 16, [40.0, 90.0], x),
        "detrend_linear": signal.detrend(x, axis=0, type="linear"),
        "detrend_constant": signal.detrend(x, axis=0, type="constant"),
    }
    for name, y in cases.items():
        write(os.path.join(out, name + ".csv"), t, y, names)
    # decimate: anti-alias butter(8, 0.8 / q) zero-phase, then every q-th sample.
    q = 4
    y = sosfiltfilt("lowpass", 8, 0.8 * FS / 2 / q, x)[::q]
    write(os.path.join(out, "decimate4.csv"), t[::q], y, names)
    # The whole chain: channel b then a, window 0.2..1.7 s, linear detrend,
    # band-pass order 4 5..100 Hz, decimate by 2.
    w = (t >= 0.2 - 0.5 / FS) & (t <= 1.7 + 0.5 / FS)
    y = signal.detrend(x[w][:, ::-1], axis=0, type="linear")
    y = sosfiltfilt("bandpass", 4, [5.0, 100.0], y)
    y = sosfiltfilt("lowpass", 8, 0.8 * FS / 2 / 2, y)[::2]
    write(os.path.join(out, "chain.csv"), t[w][::2], y, ["b", "a"])


if __name__ == "__main__":
    main()
