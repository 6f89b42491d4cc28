"""A covering directory (``rotleak covering --out DIR``): f_L, one panel per covering (an omega at a delta), f_L(s)
against s, each panel titled by its omega, delta and N, its zero measure and cv in the caption."""
from __future__ import annotations

import os

import matplotlib.pyplot as plt

from ..readers import PathLike, read_summary_and_table
from . import TWO_COLUMN, Drawing, styled
from . import draw as _draw


@styled
def figures(directory: PathLike) -> list[Drawing]:
    """f_L of a covering directory (``rotleak covering --out DIR``)."""
    summary, table = read_summary_and_table(os.fspath(directory), "f_L.csv")
    s = table["s"].astype(float).tolist()
    cov = summary["covering"]
    cov = cov if isinstance(cov, list) else [cov]
    columns = [c for c in table.columns if c != "s"]  # one f_L column per covering, in the summary's order
    n = len(columns)
    fig, axes = plt.subplots(n, 1, figsize=(TWO_COLUMN, 1.1 * n + 0.5), sharex=True, squeeze=False)
    notes = []
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
        title = "omega = %s, delta = %s, N = %d" % (omega, c.get("delta", inp["delta"]), c["N"])
        notes.append("%s: zero measure %.3g, cv %.2g" % (title, c["zero_measure"], c["cv"]))
        lo, hi = min(f), max(f)
        if hi > 0 and (hi - lo) < 0.05 * hi:
            # nearly uniform (a fine covering at small delta): from 0 the axis would show a flat block and hide
            # all structure, so it spans the data, and the title says so
            pad = max((hi - lo) * 0.1, hi * 1e-9)
            ax.set_ylim(lo - pad, hi + pad)
            ax.ticklabel_format(axis="y", useOffset=False)  # the values themselves, not "+1e4" over the axis
            title += " (zoomed)"
            notes[-1] += ", f_L in [%.6g, %.6g] (the y axis zoomed to it)" % (lo, hi)
        else:
            ax.set_ylim(bottom=0)
        ax.set_title(title, loc="left")
    axes[-1][0].set_xlabel("s")
    axes[-1][0].set_xlim(0, 1)
    fig.tight_layout(pad=0.3)
    caption = ("The MUPO covering f_L(s) of a leak of width lambda = %s (d = %s, r = %s): how often a bouncing-ball "
               "crossing's N reflections cover each s. %s." % (inp["lambda"], inp.get("d", "2"), inp.get("r", "1"),
                                                              "; ".join(notes)))
    return [Drawing("f_L", fig, caption)]


def draw(directory: PathLike, formats: object = ("png",)) -> list[str]:
    """Draw a covering directory's f_L (``rotleak covering --out DIR``) in each format; returns the paths."""
    return _draw(directory, formats)  # type: ignore[arg-type]
