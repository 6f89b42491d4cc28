#!/usr/bin/python3
"""The scalar engine against the vectorised kernel on every example table: the same bytes, and the speed of each.

For each scene of data/scenes/tables/ runs ``rotleak simulate`` with ``--engine scalar`` and ``--engine simd`` (every
kernel width this CPU runs: ROTLEAK_SIMD_LANES), on one thread, with escape records and f_c in two time windows
(so every file a run can write is compared); every file but summary.json must be byte-identical, and summary.json
equal but for ``execution`` (docs/output.md). Prints a Markdown table (collisions per second of each engine, their
ratio, identical or not) and writes it as CSV. Exits 1 if any pair differs. Each engine runs `rounds` times,
alternated, and its median rate is reported (a shared machine's speed drifts between runs).

Usage: scripts/table_engines.py BUILD_DIR OUT.csv [PARTICLES (default 100000)] [ROUNDS (default 3)]
"""
import csv
import glob
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

FC = "observe.collision_density={bins = 64, windows = [[0, 20], [10, 1000]]}"


def run(build, scene, out, engine, lanes, particles):
    """One run into `out`; its collisions per second."""
    env = dict(os.environ)
    env.pop("ROTLEAK_SIMD_LANES", None)
    if lanes:
        env["ROTLEAK_SIMD_LANES"] = str(lanes)
    subprocess.run([os.path.join(build, "rotleak"), "simulate", scene, "--engine", engine, "--threads", "1",
                    "--particles", str(particles), "--set", "observe.escapes=true", "--set", FC, "--no-progress",
                    "--force", "--out", out], check=True, stdout=subprocess.DEVNULL, env=env)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["execution"]["collisions_per_second"]


def same(a, b):
    """Whether two run directories hold the same files, byte for byte (summary.json less `execution`)."""
    names = sorted(os.listdir(a))
    if names != sorted(os.listdir(b)):
        return False
    for n in names:
        with open(os.path.join(a, n), "rb") as f, open(os.path.join(b, n), "rb") as g:
            x, y = f.read(), g.read()
        if n == "summary.json":
            x, y = json.loads(x), json.loads(y)
            x.pop("execution"), y.pop("execution")
        if x != y:
            return False
    return True


def widths(build):
    """The kernel widths this CPU runs (rotleak --version names 8 lanes where AVX-512 runs, 4 where AVX2 does)."""
    v = subprocess.run([os.path.join(build, "rotleak"), "--version"], check=True, capture_output=True, text=True)
    return [4, 8] if "8 lanes" in v.stdout else [4] if "4 lanes" in v.stdout else []


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    build, out_csv = argv[1], argv[2]
    if not widths(build):
        print("table_engines.py: this CPU runs no vectorised kernel (rotleak --version): nothing to compare",
              file=sys.stderr)
        return 3
    particles = int(argv[3]) if len(argv) > 3 else 100000
    rounds = int(argv[4]) if len(argv) > 4 else 3
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    scenes = sorted(glob.glob(os.path.join(root, "data", "scenes", "tables", "*.toml")))
    work = tempfile.mkdtemp(prefix="rotleak_engines_")
    rows, bad = [], 0
    try:
        for scene in scenes:
            name = os.path.basename(scene)[:-5]
            for lanes in widths(build):
                scalar, simd = [], []
                for _ in range(rounds):
                    scalar.append(run(build, scene, os.path.join(work, "a"), "scalar", 0, particles))
                    simd.append(run(build, scene, os.path.join(work, "b"), "simd", lanes, particles))
                identical = same(os.path.join(work, "a"), os.path.join(work, "b"))
                bad += not identical
                a, b = statistics.median(scalar), statistics.median(simd)
                rows.append({"table": name, "lanes": lanes, "scalar_collisions_per_s": "%.4g" % a,
                             "simd_collisions_per_s": "%.4g" % b, "ratio": "%.2f" % (b / a),
                             "identical": "yes" if identical else "NO"})
    finally:
        shutil.rmtree(work, ignore_errors=True)
    with open(out_csv + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(out_csv + ".tmp", out_csv)
    print("| table | lanes | scalar (collisions/s) | simd (collisions/s) | simd / scalar | files identical |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %d | %s | %s | %s | %s |" % (r["table"], r["lanes"], r["scalar_collisions_per_s"],
                                                  r["simd_collisions_per_s"], r["ratio"], r["identical"]))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
