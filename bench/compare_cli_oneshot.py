"""One-shot CLI cost (issue 13 item 1): the whole-process CPU time (user + sys,
from wait4) of `podid cwt` and `podid pod` on the same file, interleaved in one
run so both see the same load, as medians and a ratio.

Usage: python3 bench/compare_cli_oneshot.py PODID [DATA] [REPEATS] [-- extra cwt args]
Each process starts with an empty XDG_CACHE_HOME (no FFTW wisdom: what a new
user pays); a second cwt series runs with wisdom measured by `podid plan`.
Pin the script (taskset -c 0) so every child runs on the same core."""

import os
import statistics
import subprocess
import sys
import tempfile


def cpu_seconds(command, env):
    """User + system CPU seconds of one run of command (stdout discarded)."""
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    if status != 0:
        raise SystemExit("failed: " + " ".join(command))
    return usage.ru_utime + usage.ru_stime


def main():
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[:args.index("--")]
    podid = args[0]
    data = args[1] if len(args) > 1 else "examples/measured_knl50_T1.0.csv"
    repeats = int(args[2]) if len(args) > 2 else 15
    with tempfile.TemporaryDirectory() as empty, tempfile.TemporaryDirectory() as planned:
        cold = dict(os.environ, XDG_CACHE_HOME=empty)
        warm = dict(os.environ, XDG_CACHE_HOME=planned)
        subprocess.run([podid, "plan", data], env=warm, check=True, stdout=subprocess.DEVNULL)
        commands = {
            "pod": ([podid, "pod", data], cold),
            "cwt": ([podid, "cwt", data, "--channel", "w6"] + extra, cold),
            "cwt (wisdom)": ([podid, "cwt", data, "--channel", "w6"] + extra, warm),
            "--help": ([podid, "--help"], cold),
        }
        times = {name: [] for name in commands}
        for _ in range(repeats):
            for name, (command, env) in commands.items():
                times[name].append(cpu_seconds(command, env))
    median = {name: 1e3 * statistics.median(t) for name, t in times.items()}
    load = os.getloadavg()[0]
    print("whole-process CPU time, median of %d interleaved runs (load %.1f):" % (repeats, load))
    for name, ms in median.items():
        print("  %-14s %7.1f ms" % (name, ms))
    print("ratio cwt / pod: %.2fx (no wisdom), %.2fx (with wisdom); target <= 3x"
          % (median["cwt"] / median["pod"], median["cwt (wisdom)"] / median["pod"]))


if __name__ == "__main__":
    main()
