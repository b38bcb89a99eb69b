#!/usr/bin/env python3
"""The one-dof Duffing oscillator (a 1x1 imported-matrices case) simulated by
`podid simulate` against scipy's DOP853 (an independent explicit Runge-Kutta
integrator of order 8 run at rtol 1e-12), with Newmark's second order checked
by halving the step.

    m x'' + c x' + k x + k3 x^3 = 0,  x(0) = x0, x'(0) = 0

Usage: python3 tests/duffing_dop853.py PODID
"""
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.integrate import solve_ivp

M, K, C, K3, X0 = 1.0, (2 * np.pi * 5.0) ** 2, 0.4, 1.0e5, 0.1  # kg, N/m, N s/m, N/m^3, m
DURATION = 2.0  # s: about 15 periods of the hardened oscillator

CASE = """# Duffing oscillator: a 1x1 imported model with a cubic spring
[model]
type = "matrices"
mass = "m.mtx"
stiffness = "k.mtx"
damping = "c.mtx"

[[nonlinearity]]
type = "cubic"
dof = 1
k3 = {k3}

[initial]
displacement = [{x0}]

[time]
duration = {duration}
step = {step}

[sensors]
dofs = [1]
names = ["x"]

[integrator]
tolerance = 1e-13
"""


def write_scalar_mtx(path, value):
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 {:.17g}\n".format(value))


def podid_run(podid, folder, step):
    case = os.path.join(folder, "duffing.toml")
    with open(case, "w") as f:
        f.write(CASE.format(k3=K3, x0=X0, duration=DURATION, step=step))
    out = os.path.join(folder, "duffing_%g.csv" % step)
    subprocess.run([podid, "simulate", case, "--no-noise", "-o", out], check=True,
                   stdout=subprocess.DEVNULL)
    with open(out) as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t", "x"], rows[0]
    data = np.array(rows[1:], dtype=float)
    return data[:, 0], data[:, 1]


def reference(t):
    def rhs(_, y):
        x, v = y
        return [v, -(C * v + K * x + K3 * x ** 3) / M]
    sol = solve_ivp(rhs, (0.0, t[-1]), [X0, 0.0], method="DOP853", t_eval=t,
                    rtol=1e-12, atol=1e-15)
    assert sol.success, sol.message
    return sol.y[0]


def main():
    podid = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        write_scalar_mtx(os.path.join(folder, "m.mtx"), M)
        write_scalar_mtx(os.path.join(folder, "k.mtx"), K)
        write_scalar_mtx(os.path.join(folder, "c.mtx"), C)
        errors = []
        for step in (2e-4, 1e-4):
            t, x = podid_run(podid, folder, step)
            assert abs(t[-1] - DURATION) < 1e-9 and len(t) == round(DURATION / step) + 1
            err = np.max(np.abs(x - reference(t))) / X0
            errors.append(err)
            print("step %g s: max |x - x_DOP853| / x0 = %.3e" % (step, err))
    # Newmark's period error (omega dt)^2 / 12 (3e-6 at dt = 1e-4 s, omega up
    # to 65 rad/s) accumulates over 15 periods to a phase error of ~3e-4 rad:
    # measured 4.6e-5 of x0; the bound leaves a factor 4.
    tolerance = 2e-4
    ratio = errors[0] / errors[1]
    print("error ratio for a halved step: %.3f (second order: 4)" % ratio)
    if errors[1] > tolerance:
        sys.exit("FAIL: podid differs from DOP853 by %.3e > %.1e of x0" % (errors[1], tolerance))
    if not 3.5 < ratio < 4.5:
        sys.exit("FAIL: halving the step divided the error by %.3f, not ~4" % ratio)


if __name__ == "__main__":
    main()
