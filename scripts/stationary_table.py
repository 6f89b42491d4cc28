#!/usr/bin/python3
"""Runs the six stationary-leak scenes of the published table (docs/model.md, "Published values") and prints our kappa and alpha beside the
published ones (data/literature/stationary_leak_table.csv), as a Markdown table: each of ours with its
statistical error and its window systematic, each difference in percent and in units of our total error
(the two in quadrature; the published values' own errors are not stated).

--rotating: the rotating-leak rows instead (omega = 1, 2/3, 4/7, 22/23, 70/71, 82/83 and 100/101 on
data/scenes/stationary_sL_0.toml, mupo sampling and population splitting, t_max 20000), against the
study's alpha where data/literature/rotating.csv has one.

Usage: scripts/stationary_table.py [--particles N] [--out DIR] [--rotating]
       (default 10^7 particles for the stationary rows, 10^6 lines for the rotating ones; runs/table)"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
from fractions import Fraction

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROTATING = ["1", "2/3", "4/7", "22/23", "70/71", "82/83", "100/101"]


def literature(name):
    with open(os.path.join(root, "data", "literature", name)) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def run(scene, out, particles, sets):
    cmd = [os.path.join(root, "build", "rotleak"), "simulate", scene, "--particles", str(particles), "--out", out,
           "--force", "--json", "--no-progress"]
    for s in sets:
        cmd += ["--set", s]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(res.stderr)
    return json.loads(res.stdout)


def kappa_cells(k, published):
    """ours (stat., syst.) and, with a published value, the difference in percent and in total errors"""
    syst = k.get("window_systematic") or 0.0
    total = math.hypot(k["error"], syst)
    ours = "%.5g +- %.1g +- %.1g" % (k["value"], k["error"], syst)
    if published is None:
        return ours, "-"
    return ours, "%+.2f%% (%+.1f)" % (100 * (k["value"] / published - 1), (k["value"] - published) / total)


def alpha_cells(a, published, bound=False):
    if a["value"] is None:
        ours = "< %.3g" % a["upper_bound"] if a["upper_bound"] is not None else "-"
        if published is not None and a["upper_bound"] is not None and bound:
            return ours, "both bounds"
        if published is not None and a["upper_bound"] is not None:
            return ours, "bound %s the study's value" % ("above" if a["upper_bound"] >= published else "BELOW")
        return ours, "-"
    syst = a.get("systematic") or 0.0
    total = math.hypot(a["error"], syst)
    ours = "%.3g +- %.1g +- %.1g" % (a["value"], a["error"], syst)
    if published is None:
        return ours, "-"
    if bound:
        return ours, "within the study's bound" if a["value"] <= published else "ABOVE the study's bound"
    return ours, "%+.1f%% (%+.1f)" % (100 * (a["value"] / published - 1), (a["value"] - published) / total)


def stationary(args):
    print("| s_L | kappa (ours: stat., syst.) | kappa (lit.) | diff (total errors) | alpha (ours: stat., syst.) "
          "| alpha (lit.) | diff (total errors) | coll/s |")
    print("|---|---|---|---|---|---|---|---|")
    for row in literature("stationary_leak_table.csv"):
        scene = os.path.join(root, "data", "scenes", "stationary_sL_%s.toml" % row["s_L"])
        s = run(scene, os.path.join(args.out, "sL_%s" % row["s_L"]), args.particles or 10_000_000, [])
        kl, al = float(row["kappa"]), float(row["alpha"])
        kappa, kdiff = kappa_cells(s["kappa"], kl)
        alpha, adiff = alpha_cells(s["alpha"], al)
        print("| %s | %s | %.4g | %s | %s | %.3g | %s | %.3g |" %
              (row["s_L"], kappa, kl, kdiff, alpha, al, adiff, s["execution"]["collisions_per_second"]), flush=True)
    print("\n%d particles per row, %d threads; fits: %s" %
          (s["particles"], s["execution"]["threads"], s["kappa"]["method"]))


def rotating(args):
    published = {Fraction(r["omega"]): r for r in literature("rotating.csv") if r["quantity"] == "alpha"}
    scene = os.path.join(root, "data", "scenes", "stationary_sL_0.toml")
    print("| omega | kappa (ours: stat., syst.) | alpha (ours: stat., syst.) | alpha (study) | diff (total errors) "
          "| tail, regime | wall s |")
    print("|---|---|---|---|---|---|---|")
    for w in ROTATING:
        s = run(scene, os.path.join(args.out, "omega_%s" % w.replace("/", "_")), args.particles or 1_000_000,
                ["leak.omega=%s" % w, "ensemble.sampling=mupo", "run.splitting=true", "run.t_max=20000"])
        pub = published.get(Fraction(w))
        value = float(pub["value"]) if pub else None
        bound = bool(pub) and pub["kind"] == "bound"
        kappa, _ = kappa_cells(s["kappa"], None)
        alpha, adiff = alpha_cells(s["alpha"], value, bound)
        shown = ("< " if bound else "") + pub["value"] if pub else "not published"
        print("| %s | %s | %s | %s | %s | %s, %s | %.1f |" %
              (w, kappa, alpha, shown, adiff, s["tail"]["class"], s["tail"]["regime"],
               s["execution"]["wall_seconds"]), flush=True)
    print("\n%d lines per row (mupo sampling, population splitting), %d threads" %
          (s["particles"], s["execution"]["threads"]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--particles", type=int, default=None)
    ap.add_argument("--out", default=os.path.join(root, "runs", "table"))
    ap.add_argument("--rotating", action="store_true")
    args = ap.parse_args()
    rotating(args) if args.rotating else stationary(args)


if __name__ == "__main__":
    main()
