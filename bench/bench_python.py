#!/usr/bin/python3
"""rotleak.simulate in process against the command line, on the same scene and particles: wall time of
the whole call each way (the command: process start, run, files written; Python: the run and the
bytes handed over, then parsed into the Run), alternated over several rounds so that drift on a shared
machine hits both. Reports min and median of each and the ratio of the medians; never fails on time.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [ROTLEAK] [PARTICLES] [ROUNDS]
(defaults: build/rotleak 1000000 7)"""
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import rotleak

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rotleak")
    particles = int(sys.argv[2]) if len(sys.argv) > 2 else 1000000
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 7
    scene = os.path.join(ROOT, "data", "scenes", "quickstart.toml")
    work = tempfile.mkdtemp(prefix="rotleak-bench-python-")
    cli, py = [], []
    try:
        for k in range(rounds):
            out = os.path.join(work, "run%d" % k)
            t0 = time.perf_counter()
            subprocess.run([binary, "simulate", scene, "--particles", str(particles), "--out", out, "--no-progress"],
                           check=True, stdout=subprocess.DEVNULL)
            cli.append(time.perf_counter() - t0)
            shutil.rmtree(out)
            t0 = time.perf_counter()
            r = rotleak.simulate(scene, particles=particles)
            r.survival  # parsed, as a user would
            py.append(time.perf_counter() - t0)
    finally:
        shutil.rmtree(work)
    print("quick-start scene, %d particles, %d rounds alternated (rotleak %s, %d threads)" % (
        particles, rounds, rotleak.__version__, r.summary["execution"]["threads"]))
    print("| way | min (s) | median (s) |")
    print("|---|---|---|")
    print("| rotleak simulate (command line) | %.3f | %.3f |" % (min(cli), statistics.median(cli)))
    print("| rotleak.simulate (in process) | %.3f | %.3f |" % (min(py), statistics.median(py)))
    print("in process / command line (medians): %.3f" % (statistics.median(py) / statistics.median(cli)))


if __name__ == "__main__":
    main()
