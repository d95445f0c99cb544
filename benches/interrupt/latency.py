#!/usr/bin/env python3
"""Time from Ctrl-C (SIGINT) to exit, for every stage of `radiosity solve` and `render`.

Usage: python3 benches/interrupt/latency.py [--bin target/release/radiosity] [--runs 10]
           [--seed 1] [STAGE ...]

Each stage is a command whose run spends the window [a, b] seconds (after its start) in that
stage on the development machine. The signal goes at a uniformly random moment of the window
(seeded), and the script measures the time from the signal to the process's exit, checks the
exit status (130) and that stderr's last line names the expected stage (a run that lands
in another stage, on a loaded machine, is reported and not counted). Prints one line per
stage: runs, the stage each run was stopped in, and the largest and median latency.
"""

import argparse
import json
import os
import random
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time

# name: (arguments, window in seconds, a pattern the last stderr line starts with)
STAGES = {
    "meshing": (["render", "solids", "-o", "{out}/x.png"], (0.4, 1.8),
                r"interrupted while meshing"),
    "form-factors": (["solve", "cornell", "--stats", "{out}/s.json"], (0.5, 5.0),
                     r"interrupted after 0 iterations"),
    # The sweeps follow the form factors: their window is measured by a first, whole run
    # (`None`: from its stats, the middle of the sweeps).
    "gauss-seidel": (["solve", "cornell", "--elements", "6000", "--rays", "1", "--quadrature",
                      "1", "--tolerance", "1e-300", "--max-iterations", "100000000",
                      "--stats", "{out}/s.json"], None, r"interrupted after [1-9]"),
    "jacobi": (["solve", "cornell", "--solver", "jacobi", "--elements", "6000", "--rays", "1",
                "--quadrature", "1", "--tolerance", "1e-300", "--max-iterations", "100000000",
                "--stats", "{out}/s.json"], None, r"interrupted after [1-9]"),
    "progressive": (["solve", "cornell", "--solver", "progressive", "--elements", "3000",
                     "--tolerance", "1e-12", "--stats", "{out}/s.json"], (0.5, 5.0),
                    r"interrupted after [1-9]"),
    "hierarchical": (["solve", "cornell", "--solver", "hierarchical", "--epsilon", "1e-7",
                      "--stats", "{out}/s.json"], (0.5, 6.0), r"interrupted after"),
    "render-raster": (["render", "cornell", "--elements", "300", "--rays", "4",
                       "--width", "16384", "--height", "16384", "--samples", "16",
                       "-o", "{out}/x.png"], (2.5, 6.0), r"interrupted while rendering"),
    "render-raytrace": (["render", "cornell-spheres", "--elements", "300", "--rays", "4",
                         "--mode", "raytrace", "--gather", "64", "-o", "{out}/x.png"],
                        (2.5, 8.0), r"interrupted while rendering"),
    "render-final": (["render", "cornell", "--elements", "300", "--rays", "4", "--mode", "final",
                      "--width", "2048", "--height", "2048", "-o", "{out}/x.png"],
                     (2.5, 8.0), r"interrupted while rendering"),
}


def one(binary, args, at):
    """Runs `binary args`, sends SIGINT `at` seconds in; returns (latency, status, last line)."""
    with tempfile.TemporaryDirectory() as out:
        argv = [binary] + [a.format(out=out) for a in args]
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        time.sleep(at)
        if proc.poll() is not None:
            return None, proc.returncode, "finished before the signal"
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate()
        latency = time.monotonic() - sent
        lines = err.decode(errors="replace").strip().splitlines()
        return latency, proc.returncode, lines[-1] if lines else ""


def sweep_window(binary, args):
    """The middle of the sweeps of a whole run of `binary args`: from the end of the form
    factors plus a fifth of the sweeps to the end of the form factors plus three fifths."""
    with tempfile.TemporaryDirectory() as out:
        argv = [binary] + [a.format(out=out) for a in args]
        start = time.monotonic()
        subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        total = time.monotonic() - start
        with open(os.path.join(out, "s.json")) as f:
            timings = json.load(f)["timings"]
    solve = timings["solve"]
    # Process start-up and writing are outside the stats' stages: put them before the sweeps.
    before = total - solve
    return before + 0.2 * solve, before + 0.6 * solve


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default="target/release/radiosity")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("stages", nargs="*", default=list(STAGES))
    opts = parser.parse_args()
    rng = random.Random(opts.seed)
    worst_overall = 0.0
    for name in opts.stages:
        args, window, expect = STAGES[name]
        a, b = window or sweep_window(os.path.abspath(opts.bin), args)
        latencies, problems = [], []
        for _ in range(opts.runs):
            at = rng.uniform(a, b)
            latency, status, last = one(os.path.abspath(opts.bin), args, at)
            if latency is None or status != 130 or not re.match(expect, last):
                problems.append(f"at {at:.2f} s: status {status}, {last!r}")
                continue
            latencies.append(latency)
        if latencies:
            worst_overall = max(worst_overall, max(latencies))
            print(f"{name:16} {len(latencies)}/{opts.runs} runs stopped in the stage; latency "
                  f"max {max(latencies):.3f} s, median {statistics.median(latencies):.3f} s",
                  flush=True)
        for p in problems:
            print(f"{name:16} {p}", flush=True)
    print(f"largest latency: {worst_overall:.3f} s")


if __name__ == "__main__":
    sys.exit(main())
