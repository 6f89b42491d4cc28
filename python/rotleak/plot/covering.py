"""A covering directory (``rotleak covering --out DIR``): f_L.png, one panel per covering (an omega at a
delta), f_L(s) against s, each panel with its own N, zero measure and cv."""
from __future__ import annotations

import os

import matplotlib.pyplot as plt

from ..readers import PathLike, read_summary_and_table
from . import save


def draw(directory: PathLike) -> list[str]:
    """Draw a covering directory's f_L.png (``rotleak covering --out DIR``); returns its path."""
    run = os.fspath(directory)
    summary, table = read_summary_and_table(run, "f_L.csv")
    s = table["s"].astype(float).tolist()
    cov = summary["covering"]
    cov = cov if isinstance(cov, list) else [cov]
    columns = [c for c in table.columns if c != "s"]  # one f_L column per covering, in the summary's order
    n = len(columns)
    fig, axes = plt.subplots(n, 1, figsize=(9, 1.9 * n + 0.8), sharex=True, squeeze=False)
    inp = summary["input"]
    for k in range(n):
        ax = axes[k][0]
        c = cov[k]
        f: list[float] = table[columns[k]].astype(float).tolist()
        ax.fill_between(s, f, step="mid", lw=0.6, color="C%d" % (k % 10))
        ax.set_ylabel("f_L")
        # each covering names its own delta and N (with several deltas they differ panel by panel), above its
        # panel where it hides no data; the omega's label may carry "@ delta", which is not repeated
        omega = str(c["omega"]).split(" @ ")[0]
        title = "omega = %s, delta = %s, N = %d: zero measure %.3g, cv %.2g" % (
            omega, c.get("delta", inp["delta"]), c["N"], c["zero_measure"], c["cv"])
        lo, hi = min(f), max(f)
        if hi > 0 and (hi - lo) < 0.05 * hi:
            # nearly uniform (a fine covering at small delta): from 0 the axis would show a flat block and hide
            # all structure, so it spans the data, and the title says so
            pad = max((hi - lo) * 0.1, hi * 1e-9)
            ax.set_ylim(lo - pad, hi + pad)
            ax.ticklabel_format(axis="y", useOffset=False)  # the values themselves, not "+1e4" over the axis
            title += "   (y axis zoomed: f_L in [%.6g, %.6g])" % (lo, hi)
        else:
            ax.set_ylim(bottom=0)
        ax.set_title(title, loc="left", fontsize=9)
    axes[-1][0].set_xlabel("s")
    axes[-1][0].set_xlim(0, 1)
    fig.suptitle("MUPO covering f_L(s): lambda = %s (N: reflections of a crossing)" % inp["lambda"])
    fig.tight_layout()
    path = os.path.join(run, "f_L.png")
    save(fig, path)
    return [path]
