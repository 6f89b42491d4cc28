#!/usr/bin/python3
"""Turn and schedule invariance of population splitting, as the tables of docs/guide/tails.md: omega = 100/101 (no tail, P
falls to ~1e-16 by t = 8000), mupo + splitting, each setting an independent seed; P +- P_err at
t = 1000, 1500 and 2000 (P ~ 1e-2, 1e-3, 1e-4: where 2*10^5 lines resolve P; later the allowance for
unsplit lines not drawn is most of P's error, docs/model.md) and its deviation from the default setting
in combined standard errors.

Usage: bench/splitting_invariance.py [ROTLEAK] [LINES]   (defaults: build/rotleak 200000)"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMES = (1000, 1500, 2000)


def run(rotleak, out, lines, seed, extra):
    cmd = [rotleak, "simulate", os.path.join(ROOT, "data", "scenes", "stationary_sL_0.toml"), "--particles",
           str(lines), "--set", "leak.omega=100/101", "--set", "run.t_max=8000", "--set", "ensemble.sampling=mupo",
           "--set", "run.splitting=true", "--set", "ensemble.seed=%d" % seed, "--out", out, "--force", "--no-progress"]
    for kv in extra:
        cmd += ["--set", kv]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "survival.csv"), newline="") as f:
        rows = {float(r["t"]): (float(r["P"]), float(r["P_err"])) for r in csv.DictReader(f)}
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return [rows[t] for t in TIMES], s["execution"]["wall_seconds"], s["collisions"]


def table(rotleak, lines, work, key, values, default, seed0):
    results = {}
    for k, v in enumerate(values):
        results[v] = run(rotleak, os.path.join(work, "%s_%s" % (key, v)), lines, seed0 + k, ["run.%s=%s" % (key, v)])
    print("| run.%s | seed | %s | wall s | collisions |" % (key, " | ".join("P(%d) (dev.)" % t for t in TIMES)))
    print("|" + "---|" * (4 + len(TIMES)))
    ref = results[default][0]
    for k, v in enumerate(values):
        pts, wall, coll = results[v]
        cells = []
        for (P, e), (P0, e0) in zip(pts, ref):
            if P == 0:  # a schedule slower than the decay: the lines died out
                cells.append("0 (no line left)")
                continue
            dev = "" if v == default else " (%+.1f)" % ((P - P0) / math.hypot(e, e0))
            cells.append("%.4g +- %.2g%s" % (P, e, dev))
        print("| %s%s | %d | %s | %.1f | %.3g |" % (v, " (default)" if v == default else "", seed0 + k,
                                                     " | ".join(cells), wall, coll))
    print()


def main():
    rotleak = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rotleak")
    lines = int(sys.argv[2]) if len(sys.argv) > 2 else 200000
    work = tempfile.mkdtemp()
    try:
        print("omega = 100/101, %d lines each (mupo + splitting), an independent seed per row; dev.: the difference "
              "from the default row in combined standard errors\n" % lines)
        table(rotleak, lines, work, "split_delta", ["1e-6", "1e-9", "1e-12", "1e-14", "1e-15"], "1e-12", 61)
        table(rotleak, lines, work, "split_every", ["100", "150", "151.2316695704561", "200", "300"],
              "151.2316695704561", 71)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
