#!/usr/bin/env python3
"""Runs the six stationary-leak scenes of the published table (docs/model.md, "Published values") and prints our kappa and alpha beside the
published ones (data/literature/stationary_leak_table.csv), as a Markdown table: each of ours with its
statistical error and its window systematic, each difference in percent and in units of our total error
(the two in quadrature; the published values' own errors are not stated).

Usage: scripts/stationary_table.py [--particles N] [--out DIR]   (default 10^7 particles, runs/table)"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--particles", type=int, default=10_000_000)
    ap.add_argument("--out", default=os.path.join(root, "runs", "table"))
    args = ap.parse_args()
    with open(os.path.join(root, "data", "literature", "stationary_leak_table.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    print("| s_L | kappa (ours: stat., syst.) | kappa (lit.) | diff (total errors) | alpha (ours: stat., syst.) "
          "| alpha (lit.) | diff (total errors) | coll/s |")
    print("|---|---|---|---|---|---|---|---|")
    for row in rows:
        scene = os.path.join(root, "data", "scenes", "stationary_sL_%s.toml" % row["s_L"])
        out = os.path.join(args.out, "sL_%s" % row["s_L"])
        res = subprocess.run([os.path.join(root, "build", "rotleak"), "simulate", scene, "--particles",
                              str(args.particles), "--out", out, "--force", "--json", "--no-progress"],
                             capture_output=True, text=True)
        if res.returncode != 0:
            sys.exit(res.stderr)
        s = json.loads(res.stdout)
        k, a = s["kappa"], s["alpha"]
        kl, al = float(row["kappa"]), float(row["alpha"])
        k_syst = k.get("window_systematic") or 0.0
        k_total = math.hypot(k["error"], k_syst)
        kappa = "%.5g +- %.1g +- %.1g" % (k["value"], k["error"], k_syst)
        kdiff = "%+.2f%% (%+.1f)" % (100 * (k["value"] / kl - 1), (k["value"] - kl) / k_total)
        if a["value"] is not None:
            a_syst = a.get("systematic") or 0.0
            a_total = math.hypot(a["error"], a_syst)
            alpha = "%.3g +- %.1g +- %.1g" % (a["value"], a["error"], a_syst)
            adiff = "%+.1f%% (%+.1f)" % (100 * (a["value"] / al - 1), (a["value"] - al) / a_total)
        else:
            alpha, adiff = "< %.3g" % a["upper_bound"], "-"
        print("| %s | %s | %.4g | %s | %s | %.3g | %s | %.3g |" %
              (row["s_L"], kappa, kl, kdiff, alpha, al, adiff, s["execution"]["collisions_per_second"]), flush=True)
    print("\n%d particles per row, %d threads; fits: %s" % (args.particles, s["execution"]["threads"], k["method"]))


if __name__ == "__main__":
    main()
