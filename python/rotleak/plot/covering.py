"""A covering directory (``rotleak covering --out DIR``): f_L.png, one panel per covering (an omega at a
delta), f_L(s) against s, each panel with its own N, zero measure and cv."""
import json
import os

import matplotlib.pyplot as plt

from . import read_csv, save


def draw(run):
    """Draws f_L.png; returns its path."""
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    header, rows = read_csv(os.path.join(run, "f_L.csv"))
    s = [float(r[0]) for r in rows]
    cov = summary["covering"]
    cov = cov if isinstance(cov, list) else [cov]
    n = len(header) - 1
    fig, axes = plt.subplots(n, 1, figsize=(9, 1.6 * n + 0.8), sharex=True, squeeze=False)
    inp = summary["input"]
    for k in range(n):
        ax = axes[k][0]
        c = cov[k]
        ax.fill_between(s, [float(r[k + 1]) for r in rows], step="mid", lw=0.6, color="C%d" % (k % 10))
        ax.set_ylabel("f_L")
        # each covering names its own delta and N: with several deltas they differ panel by panel
        ax.text(0.995, 0.92, "omega = %s, delta = %s, N = %d   zero measure %.3g, cv %.2g" %
                (c["omega"], c.get("delta", inp["delta"]), c["N"], c["zero_measure"], c["cv"]),
                transform=ax.transAxes, ha="right", va="top", fontsize=9,
                bbox=dict(facecolor="white", alpha=0.85, lw=0))
        ax.set_ylim(bottom=0)
    axes[-1][0].set_xlabel("s")
    axes[-1][0].set_xlim(0, 1)
    fig.suptitle("MUPO covering f_L(s): lambda = %s (N: reflections of a crossing)" % inp["lambda"])
    fig.tight_layout()
    path = os.path.join(run, "f_L.png")
    save(fig, path)
    return [path]
