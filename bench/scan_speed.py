#!/usr/bin/python3
"""Wall time of a 15-point omega scan with population splitting: the stationary scene over 15 omegas from the
low, mid and high regimes, 10^5 lines a point, importance sampling (mupo) and splitting, every point run by
`rotleak scan` itself. Several binaries (two builds of the suite, say) are run in alternation, so that each
sees the same load on a shared machine; prints each scan's wall time, the medians and, for two binaries, the
ratio of the first's median to the second's, and whether the two scans' table.csv are byte-identical.

Usage: /usr/bin/python3 bench/scan_speed.py [--binary build/rotleak ...] [--runs 3] [--particles 100000] [--threads 0 (all)]
"""
import argparse
import hashlib
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OMEGAS = "1e-5,2e-5,5e-5,1e-4,2e-4,1e-3,1/3,1/2,2/3,3/4,22/23,70/71,82/83,100/101,ln(19)"


def scan(binary, particles, threads, out):
    cmd = [binary, "scan", os.path.join(ROOT, "data/scenes/stationary_sL_0.toml"), "--over", "leak.omega=" + OMEGAS,
           "--particles", str(particles), "--set", "ensemble.sampling=mupo", "--set", "run.splitting=true",
           "--no-progress", "--out", out]
    if threads:
        cmd += ["--threads", str(threads)]
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    with open(os.path.join(out, "table.csv"), "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    return seconds, digest


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", nargs="+", default=[os.path.join(ROOT, "build/rotleak")])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--particles", type=int, default=100000)
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    if a.runs < 1 or a.particles < 1:
        sys.exit("scan_speed: --runs and --particles must be at least 1")
    for b in a.binary:
        if not os.access(b, os.X_OK):
            sys.exit(f"scan_speed: --binary {b} is not an executable (build it: bash scripts/build.sh)")
    work = tempfile.mkdtemp(prefix="rotleak-scan-")
    try:
        times = {b: [] for b in a.binary}
        digests = {b: set() for b in a.binary}
        for i in range(a.runs):
            for k, b in enumerate(a.binary):
                out = os.path.join(work, f"scan{k}-{i}")
                seconds, digest = scan(b, a.particles, a.threads, out)
                times[b].append(seconds)
                digests[b].add(digest)
                shutil.rmtree(out)
                print(f"run {i + 1}/{a.runs}, {b}: {seconds:.1f} s", flush=True)
        medians = [statistics.median(times[b]) for b in a.binary]
        for b, m in zip(a.binary, medians):
            print(f"{b}: median {m:.1f} s over {a.runs} scans of 15 points (table.csv sha256 {sorted(digests[b])[0][:16]})")
        if len(a.binary) == 2:
            print(f"ratio {medians[0] / medians[1]:.2f} (first / second); table.csv identical: "
                  f"{digests[a.binary[0]] == digests[a.binary[1]]}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
