"""Old/new side by side: the same Google Benchmark filter on two builds of one
benchmark program, invocations interleaved so both see the same load, medians
of the CPU and wall times per benchmark and the ratio old / new.

Usage: python3 bench/compare_builds.py OLD_BUILD NEW_BUILD FILTER [ROUNDS] [PROGRAM]
  e.g. taskset -c 0 python3 bench/compare_builds.py /tmp/old/build/release \\
           build/release 'BM_CwtFcwtCase/.*/1/0' 5 wavelet_benchmark
Each process starts with an empty XDG_CACHE_HOME (estimated FFTW plans)."""

import json
import os
import statistics
import subprocess
import sys
import tempfile


def run(program, pattern, env):
    """{name: (cpu_ms, wall_ms)} of one invocation."""
    result = subprocess.run([program, "--benchmark_filter=" + pattern,
                             "--benchmark_format=json"],
                            check=True, capture_output=True, text=True, env=env)
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    out = {}
    for record in json.loads(result.stdout)["benchmarks"]:
        factor = scale[record["time_unit"]]
        out[record["name"]] = (record["cpu_time"] * factor, record["real_time"] * factor)
    return out


def main():
    old, new, pattern = sys.argv[1], sys.argv[2], sys.argv[3]
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 5
    program = sys.argv[5] if len(sys.argv) > 5 else "wavelet_benchmark"
    times = {"old": {}, "new": {}}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, XDG_CACHE_HOME=cache)
        for _ in range(rounds):
            for label, build in (("old", old), ("new", new)):
                for name, value in run(os.path.join(build, "bench", program), pattern, env).items():
                    times[label].setdefault(name, []).append(value)
    print("median of %d interleaved invocations, load %.1f; ratio = old / new (> 1: new faster)"
          % (rounds, os.getloadavg()[0]))
    print("%-44s %12s %12s %8s %12s" % ("benchmark", "old CPU ms", "new CPU ms", "ratio",
                                        "new wall ms"))
    for name in times["new"]:
        if name not in times["old"]:
            continue
        o = statistics.median(c for c, _ in times["old"][name])
        n = statistics.median(c for c, _ in times["new"][name])
        wall = statistics.median(w for _, w in times["new"][name])
        print("%-44s %12.3f %12.3f %7.2fx %12.3f" % (name, o, n, o / n, wall))


if __name__ == "__main__":
    main()
