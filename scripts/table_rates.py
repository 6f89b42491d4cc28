#!/usr/bin/python3
"""The escape rate of a small stationary hole on every standard table, against the small-hole rate.

For each table of docs/tables.md and two hole widths lambda (a share of the outer boundary's length), runs
``rotleak simulate`` (uniform Birkhoff starts, the hole centred at s = 0) and fits kappa on
[T/2, 3 T], T = 1 / kappa0 with kappa0 = lambda |boundary| / (pi Area) the small-hole rate (summary.json's
``table.small_hole_rate``): the rate a hole would give if the flow were ergodic and the particles forgot
where they were between visits to it. Prints a Markdown table (kappa / kappa0 with its error, and P(3 T), which
for an exponential decay at kappa0 would be e^-3 = 0.050) and writes the runs' numbers as CSV.

Usage: scripts/table_rates.py BUILD_DIR OUT.csv [PARTICLES]   (default 100000)
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

TABLES = [
    ("stadium", '[table]\nkind = "stadium"\nd = "2"\nr = "1"\n'),
    ("sinai", '[table]\nkind = "sinai"\nside = "2"\nradius = "1/2"\n'),
    ("mushroom", '[table]\nkind = "mushroom"\nradius = "1"\nstem_width = "1/2"\nstem_height = "1"\n'),
    ("annulus", '[table]\nkind = "annulus"\nradius = "1"\ninner_radius = "1/4"\noffset = "-1/3"\n'),
    ("lemon", '[table]\nkind = "lemon"\nradius = "1"\ndistance = "1"\n'),
    ("lorentz", '[table]\nkind = "lorentz"\nradius = "0.45"\n'),
    ("polygon", '[table]\nkind = "polygon"\nvertices = [["0", "0"], ["0", "1"], ["2", "1/3"]]\n'),
    ("circle", '[table]\nkind = "circle"\nradius = "1"\n'),
    ("ellipse", '[table]\nkind = "ellipse"\na = "2"\nb = "1"\n'),
]
WIDTHS = ("0.02", "0.01")


def run(build, work, name, table, width, particles):
    """One run; its summary.json and survival.csv rows."""
    scene = os.path.join(work, "%s_%s.toml" % (name, width))
    with open(scene, "w") as f:
        f.write(table + '\n[leak]\nwidth = "%s"\n' % width)
    if name == "stadium":  # the stadium's summary has no "table": its rate in closed form, lambda L / (pi A)
        d, r = 2.0, 1.0
        k0 = float(width) * (2 * d + 2 * math.pi * r) / (math.pi * (2 * d * r + math.pi * r * r))
    else:  # the small-hole rate from rotleak itself (a run of one particle)
        probe = os.path.join(work, "probe")
        subprocess.run([os.path.join(build, "rotleak"), "simulate", scene, "--particles", "1", "--no-progress",
                        "--force", "--out", probe], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(probe, "summary.json")) as f:
            k0 = json.load(f)["table"]["small_hole_rate"]
    t = 1 / k0
    out = os.path.join(work, "%s_%s" % (name, width))
    subprocess.run([os.path.join(build, "rotleak"), "simulate", scene, "--particles", str(particles),
                    "--set", "run.t_max=%r" % (3.5 * t), "--set", "fit.kappa_window=[%r, %r]" % (t / 2, 3 * t),
                    "--set", "observe.survival_dt=%r" % (t / 100), "--no-progress", "--out", out], check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(out, "survival.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    p3 = min(rows, key=lambda r: abs(float(r["t"]) - 3 * t))
    return s, k0, p3


def rate_row(name, width, s, k0):
    """A run's fitted kappa against kappa0: the CSV row's columns from `table` to `ratio_err` (docs/output.md)."""
    k = s["kappa"]
    ratio = k["value"] / k0 if k["value"] is not None else float("nan")
    err = math.hypot(k["error"], k["window_systematic"]) / k0 if k["value"] is not None else float("nan")
    return {"table": name, "width": width, "kappa0": k0, "kappa": k["value"], "kappa_err": k["error"],
            "kappa_syst": k["window_systematic"], "ratio": ratio, "ratio_err": err}


def write_csv(path, rows):
    """The rows as CSV with their keys as the header: a temporary name, then a rename (never half a file)."""
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    build, out_csv = sys.argv[1], sys.argv[2]
    particles = int(sys.argv[3]) if len(sys.argv) > 3 else 100000
    work = tempfile.mkdtemp(prefix="rotleak-rates-")
    lines = []
    try:
        for name, table in TABLES:
            for width in WIDTHS:
                s, k0, p3 = run(build, work, name, table, width, particles)
                row = rate_row(name, width, s, k0)
                row.update({"P_3T": float(p3["P"]), "P_3T_err": float(p3["P_err"])})
                row.update({"particles": particles, "collisions": s["collisions"]})
                lines.append(row)
                k = s["kappa"]
                print("%-9s lambda %s: kappa0 %.5g  kappa %.5g +- %.2g  ratio %.3f +- %.3f  P(3T) %.4f" % (
                    name, width, k0, k["value"] or float("nan"), k["error"] or float("nan"), row["ratio"],
                    row["ratio_err"], float(p3["P"])), flush=True)
    finally:
        shutil.rmtree(work)
    write_csv(out_csv, lines)
    print("\n| table | lambda | kappa0 | kappa / kappa0 | P(3 / kappa0) |\n|---|---|---|---|---|")
    for r in lines:
        print("| %s | %s | %.4g | %.3f +- %.3f | %.4f +- %.4f |" % (r["table"], r["width"], r["kappa0"], r["ratio"],
                                                                    r["ratio_err"], r["P_3T"], r["P_3T_err"]))


if __name__ == "__main__":
    main()
