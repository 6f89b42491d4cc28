"""A shadow directory (``rotleak shadow --out DIR``): shadow.png, the divergence from the MPFR truth per
collision for every tier (log scale), MUPO phases shaded, the tolerance and the truth's escape marked."""
from __future__ import annotations

import os

import matplotlib.pyplot as plt

from ..readers import PathLike, read_summary_and_table
from . import save


def draw(directory: PathLike) -> list[str]:
    """Draw a shadow directory's shadow.png (``rotleak shadow --out DIR``); returns its path."""
    run = os.fspath(directory)
    summary, table = read_summary_and_table(run, "shadow.csv")
    k = table["k"].astype(int).tolist()
    fig, ax = plt.subplots(figsize=(10, 5))
    for i, mupo in enumerate(table["mupo"].tolist()):
        if mupo == 1:
            ax.axvspan(k[i] - 0.5, k[i] + 0.5, color="0.85", lw=0)
    for t in summary["tiers"]:
        div = table["div_" + t["name"]].tolist()
        pts = [(k[i], float(d)) for i, d in enumerate(div) if d == d and d != 0]  # d != d: an empty field (NaN)
        if pts:
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], lw=1,
                        label="%s (horizon %s)" % (t["name"], t["horizon_collision"] or "-"))
    ax.axhline(summary["tolerance"], color="k", ls="--", lw=0.8, label="tolerance")
    esc = summary["truth"]["escape_collision"]
    if esc:
        ax.axvline(esc, color="C3", ls=":", lw=1, label="truth escapes")
    ax.set_xlabel("collision")
    ax.set_ylabel("divergence from the truth (max of |dt|, |dq|, |dv|)")
    ax.set_title("particle %d: truth = MPFR %d bits; grey: MUPO phases" % (summary["particle"], summary["truth"]["bits"]))
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(run, "shadow.png")
    save(fig, path)
    return [path]
