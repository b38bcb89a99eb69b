"""Shared helpers of the Python comparison scripts: timing a Python call and
reading podid's Google Benchmark medians and simulations in the same run."""

import json
import os
import subprocess
import tempfile
import time

import numpy as np

REPEATS = 5


def time_python(function, repeats=REPEATS):
    """Median wall and CPU time of function() in ms."""
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        function()
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return 1e3 * float(np.median(wall)), 1e3 * float(np.median(cpu))


def benchmark_medians(executable, pattern, repeats=REPEATS):
    """{run_name: median record} of a Google Benchmark executable's runs matching pattern."""
    result = subprocess.run([executable, "--benchmark_filter=" + pattern,
                             "--benchmark_repetitions=%d" % repeats,
                             "--benchmark_report_aggregates_only=true",
                             "--benchmark_format=json"],
                            check=True, capture_output=True, text=True)
    report = json.loads(result.stdout)
    return {r["run_name"]: r for r in report["benchmarks"] if r.get("aggregate_name") == "median"}


def to_ms(record):
    """(cpu, wall) of a benchmark record in ms."""
    scale = {"us": 1e-3, "ms": 1.0, "ns": 1e-6, "s": 1e3}[record["time_unit"]]
    return record["cpu_time"] * scale, record["real_time"] * scale


def podid_simulation(podid, extra_sets=()):
    """The sensors (samples x 6) of `podid simulate examples/beam.toml` for 1 s, noise-free."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "sim.csv")
        command = [podid, "simulate", "examples/beam.toml", "--set", "time.duration=1.0"]
        for s in extra_sets:
            command += ["--set", s]
        subprocess.run(command + ["--no-noise", "-o", out], check=True, stdout=subprocess.DEVNULL)
        return np.loadtxt(out, delimiter=",", skiprows=1)[:, 1:]
