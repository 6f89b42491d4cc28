#!/usr/bin/env python3
"""Draw f_L.png from a `rotleak covering --out DIR` directory: one panel per omega, f_L(s) against s.

Usage: plot_covering.py DIR    (rotleak covering calls this). Needs Debian's python3-matplotlib."""
import os

import matplotlib.pyplot as plt

from plot_run import load_run, read_csv, run_main, save  # same folder: the shared helpers


def main():
    run, summary = load_run("plot_covering.py DIR")
    header, rows = read_csv(os.path.join(run, "f_L.csv"))
    s = [float(r[0]) for r in rows]
    cov = summary["covering"]
    cov = cov if isinstance(cov, list) else [cov]
    n = len(header) - 1
    fig, axes = plt.subplots(n, 1, figsize=(9, 1.6 * n + 0.8), sharex=True, squeeze=False)
    for k in range(n):
        ax = axes[k][0]
        c = cov[k]
        ax.fill_between(s, [float(r[k + 1]) for r in rows], step="mid", lw=0.6, color="C%d" % k)
        ax.set_ylabel("f_L")
        ax.text(0.995, 0.92, "omega = %s   zero measure %.3g, cv %.2g" % (c["omega"], c["zero_measure"], c["cv"]),
                transform=ax.transAxes, ha="right", va="top", fontsize=9,
                bbox=dict(facecolor="white", alpha=0.85, lw=0))
        ax.set_ylim(bottom=0)
    axes[-1][0].set_xlabel("s")
    axes[-1][0].set_xlim(0, 1)
    inp = summary["input"]
    fig.suptitle("MUPO covering f_L(s): delta = %s, lambda = %s, N = %d reflections" % (inp["delta"], inp["lambda"], cov[0]["N"]))
    fig.tight_layout()
    save(fig, os.path.join(run, "f_L.png"))
    print("drew " + os.path.join(run, "f_L.png"))


if __name__ == "__main__":
    run_main(main)
