#!/usr/bin/python3
"""Time 1 s of the reference case in plain numpy against podid (issue 2).

Usage: /usr/bin/python3 bench/compare_python_simulate.py [BUILD_DIR]
  (BUILD_DIR holds apps/podid and bench/simulate_benchmark, default
  build/bench; run from the repo root. Pin with `taskset -c 0` for one core.)

The numpy version is bench/python_beam.py: the same FE beam (6 elements,
consistent mass, Rayleigh 1 % on modes 1-2, cubic tip spring k3 = 50e8,
static tip deflection under 20 N), Newmark average acceleration with full
Newton per step. Sanity check that the same work is timed: its w1..w6 agree
with `podid simulate --no-noise` (time.duration = 1) to TOLERANCE relative
to the largest displacement. podid's figures are simulate_benchmark's
BM_Reference1sCondensed (time loop only) and BM_Reference1sSimulateEndToEnd
(model, modal analysis, static solve, integrator set-up and loop: the work
the Python function does), run in the same process group as this script.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import python_beam  # noqa: E402
from bench_common import REPEATS, benchmark_medians, podid_simulation, time_python  # noqa: E402

TOLERANCE = 1e-6  # max |w_py - w_podid| / max |w_podid|


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/bench"
    podid = os.path.join(build, "apps", "podid")
    bench = os.path.join(build, "bench", "simulate_benchmark")

    ours = podid_simulation(podid)
    theirs = python_beam.simulate(50.0, duration=1.0)
    if ours.shape != theirs.shape:
        print("shape mismatch: podid %s, numpy %s" % (ours.shape, theirs.shape))
        return 1
    err = np.abs(ours - theirs).max() / np.abs(ours).max()
    print("agreement, 1 s (%d samples x %d sensors): max |w_numpy - w_podid| / max |w_podid| = %.2e"
          " (tolerance %.0e)" % (ours.shape[0], ours.shape[1], err, TOLERANCE))

    py_wall, py_cpu = time_python(lambda: python_beam.simulate(50.0, duration=1.0))
    medians = benchmark_medians(bench, "BM_Reference1s(Condensed|SimulateEndToEnd)$")
    loop = medians["BM_Reference1sCondensed"]
    end = medians["BM_Reference1sSimulateEndToEnd"]
    to_ms = {"us": 1e-3, "ms": 1.0, "ns": 1e-6, "s": 1e3}
    loop_cpu, loop_wall = (loop[k] * to_ms[loop["time_unit"]] for k in ("cpu_time", "real_time"))
    end_cpu, end_wall = (end[k] * to_ms[end["time_unit"]] for k in ("cpu_time", "real_time"))
    print("time: numpy %.1f ms wall, %.1f ms CPU (median of %d)" % (py_wall, py_cpu, REPEATS))
    print("time: podid end-to-end %.3f ms CPU, %.3f ms wall; time loop %.3f ms CPU, %.3f ms wall"
          " (medians of %d repetitions)" % (end_cpu, end_wall, loop_cpu, loop_wall, REPEATS))
    print("ratio (end-to-end, the same work): %.0fx CPU/CPU, %.0fx wall/wall"
          % (py_cpu / end_cpu, py_wall / end_wall))
    print("ratio (time loop): %.0fx CPU/CPU, %.0fx wall/wall" % (py_cpu / loop_cpu, py_wall / loop_wall))
    ok = err <= TOLERANCE
    print("agreement check: %s" % ("pass" if ok else "FAIL"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
