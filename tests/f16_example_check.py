"""examples/f16/run.py's summary against an independent parse of
F16_Data.mat (scipy.io.loadmat, NumPy's SVD, scipy.signal.hilbert).
Usage: f16_example_check.py F16_Data.mat summary.json"""
import json
import sys

import numpy as np
import scipy.io
import scipy.signal

mat = scipy.io.loadmat(sys.argv[1])
summary = json.load(open(sys.argv[2]))
signal = mat["Signal_0"][0, 0]
values = signal["y_values"][0, 0]["values"]
names = [str(n[0]) for n in signal["function_record"][0, 0]["name"].ravel()]
x = signal["x_values"][0, 0]
start, step, count = (float(x[k].ravel()[0]) for k in ("start_value", "increment", "number_of_values"))

# The live channels: those not identically zero.
live = [names[j] for j in range(values.shape[1]) if np.any(values[:, j] != 0)]
live_summary = summary["live"]
assert live == live_summary["channels"], (live, live_summary["channels"])
assert summary["all_channels"]["sensors"] == values.shape[1] == 115
assert summary["all_channels"]["numerical_rank"] == len(live) == 2
assert live_summary["samples"] == values.shape[0] == int(count)
# Time from the export's start value and increment, as written (exact copies
# up to the decimal round trip of the JSON: 1e-12 relative).
kRoundTrip = 1e-12
assert abs(live_summary["start_s"] - start) <= kRoundTrip * start
assert abs(live_summary["step_s"] - step) <= kRoundTrip * step

# POD of the live channels (means removed): singular values and POMs against
# NumPy's SVD. Both are backward-stable SVDs of a 2 x 108477 matrix: relative
# 1e-9 is 1e7 x machine precision (POMs up to their sign).
kSvd = 1e-9
X = np.array([values[:, names.index(n)] for n in live])
X = X - X.mean(axis=1, keepdims=True)
u, s, _ = np.linalg.svd(X, full_matrices=False)
np.testing.assert_allclose(live_summary["singular_values"], s, rtol=kSvd)
np.testing.assert_allclose(live_summary["energy_fraction"], s**2 / np.sum(s**2), rtol=kSvd)
poms = np.array(live_summary["poms"])  # row k: POM k + 1 (modes x sensors)
for k in range(2):
    assert abs(abs(poms[k] @ u[:, k]) - 1) <= kSvd, (k, poms, u)

# The ridge IF follows the sweep: the force's instantaneous frequency from the
# phase of its analytic signal, median per 10 s slice (the sweep falls by
# ~0.05 Hz/s, so a slice's median is the frequency at its middle).
# - The force's ridge: within 1 % in every slice (0.6 % at worst here, at the
#   low-frequency end where the Hilbert IF ripples with the force's harmonics).
# - The accelerations' ridges: near the F-16's modes the response holds free
#   vibration at the mode's frequency too, and the ridge follows it for some
#   seconds (9 % off in 210-220 s); elsewhere it is the forced response.
#   Required: 80 % of the slices within 2 %, and their median within 0.5 %.
kForceRelative = 0.01
kResponseRelative = 0.02
kResponseShare = 0.8
kResponseMedianRelative = 0.005
force = mat["Signal_1"][0, 0]["y_values"][0, 0]["values"].ravel()  # one channel
phase = np.unwrap(np.angle(scipy.signal.hilbert(force - force.mean())))
inst = np.gradient(phase, step) / (2 * np.pi)
t = start + np.arange(force.size) * step  # record time, as the ridge CSVs give it
force_name = [n for n in summary["median_if_Hz"] if n not in live]
assert len(force_name) == 1, summary["median_if_Hz"].keys()
for name, slices in summary["median_if_Hz"].items():
    errors = []
    for window, median in slices.items():
        a, b = (float(v) for v in window.split("-"))
        if a < 10:  # the sweep starts at ~4 s: before, the force is noise
            continue
        reference = np.median(inst[(t >= a) & (t < b)])
        errors.append(abs(median - reference) / reference)
    errors = np.array(errors)
    assert errors.size >= 25, (name, errors.size)
    if name in force_name:
        assert errors.max() <= kForceRelative, (name, errors)
    else:
        assert np.mean(errors <= kResponseRelative) >= kResponseShare, (name, errors)
        assert np.median(errors) <= kResponseMedianRelative, (name, errors)
print(f"f16 example: {len(live)} live channels, sigma {s}; ridges follow the force's Hilbert IF")
