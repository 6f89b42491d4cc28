#!/usr/bin/python3
"""What f_c costs on top of a run: the study scene (data/study/study.toml) with importance sampling
("mupo") and fast-forward, with and without f_c windows, run in alternating pairs so that both see
the same load on a shared machine; prints each pair, the medians and their ratio, and the sha256 of
fc.csv (the same file for every run, and the same as stepping gives: the Simd and fast-forward
tests check that).

Usage: /usr/bin/python3 bench/fc_overhead.py [--binary build/rotleak] [--runs 7] [--particles 1000000]
                                    [--threads 0 (all)]
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
FC = "observe.collision_density={bins=1000,windows=[[0,20000],[2000,20000]]}"


def run(binary, particles, threads, with_fc, out):
    cmd = [binary, "simulate", os.path.join(ROOT, "data/study/study.toml"), "--particles", str(particles),
           "--set", "ensemble.sampling=mupo", "--set", "run.fast_forward=true", "--no-progress", "--out", out]
    if threads:
        cmd += ["--threads", str(threads)]
    if with_fc:
        cmd += ["--set", FC]
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=os.path.join(ROOT, "build/rotleak"))
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--particles", type=int, default=1000000)
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    if a.runs < 1 or a.particles < 1:
        sys.exit("fc_overhead: --runs and --particles must be at least 1")
    if not os.access(a.binary, os.X_OK):
        sys.exit(f"fc_overhead: --binary {a.binary} is not an executable (build it: bash scripts/build.sh)")
    work = tempfile.mkdtemp(prefix="rotleak-fc-")
    try:
        with_fc, without, hashes = [], [], set()
        for i in range(a.runs):
            out = os.path.join(work, f"fc{i}")
            with_fc.append(run(a.binary, a.particles, a.threads, True, out))
            without.append(run(a.binary, a.particles, a.threads, False, os.path.join(work, f"plain{i}")))
            with open(os.path.join(out, "fc.csv"), "rb") as f:
                hashes.add(hashlib.sha256(f.read()).hexdigest())
            print(f"pair {i + 1}/{a.runs}: with f_c {with_fc[-1]:.3f} s, without {without[-1]:.3f} s", flush=True)
            shutil.rmtree(out)
            shutil.rmtree(os.path.join(work, f"plain{i}"))
        mw, mo = statistics.median(with_fc), statistics.median(without)
        print(f"median wall: with f_c {mw:.3f} s, without {mo:.3f} s, ratio {mw / mo:.2f} "
              f"(pairs: {min(w / o for w, o in zip(with_fc, without)):.2f} .. "
              f"{max(w / o for w, o in zip(with_fc, without)):.2f})")
        print("fc.csv sha256: " + ", ".join(sorted(hashes)))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
