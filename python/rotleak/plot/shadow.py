"""A shadow directory (``rotleak shadow --out DIR``): shadow, the divergence from the MPFR truth per collision for
every tier (log scale), MUPO phases shaded, the tolerance and the truth's escape marked."""
from __future__ import annotations

import os

import matplotlib.pyplot as plt

from ..readers import PathLike, read_summary_and_table
from . import LEAK, ONE_COLUMN, Drawing, legend_below, styled
from . import draw as _draw


@styled
def figures(directory: PathLike) -> list[Drawing]:
    """shadow of a shadow directory (``rotleak shadow --out DIR``)."""
    summary, table = read_summary_and_table(os.fspath(directory), "shadow.csv")
    k = table["k"].astype(int).tolist()
    fig, ax = plt.subplots(figsize=(ONE_COLUMN, 2.9))
    for i, mupo in enumerate(table["mupo"].tolist()):
        if mupo == 1:
            ax.axvspan(k[i] - 0.5, k[i] + 0.5, color="0.85", lw=0)
    ax.plot([], [], color="0.85", lw=6, label="MUPO phase")
    horizons = []
    for n, t in enumerate(summary["tiers"]):
        div = table["div_" + t["name"]].tolist()
        pts = [(k[i], float(d)) for i, d in enumerate(div) if d == d and d != 0]  # d != d: an empty field (NaN)
        horizons.append("%s %s" % (t["name"], t["horizon_collision"] or "none"))
        if pts:  # C3 is the escape's colour: the tiers skip it
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], lw=0.8, color="C%d" % (n if n < 3 else n + 1),
                        label=t["name"])
    ax.axhline(summary["tolerance"], color="k", ls="--", lw=0.8, label="tolerance")
    esc = summary["truth"]["escape_collision"]
    if esc:
        ax.axvline(esc, color=LEAK, ls=":", lw=1, label="truth escapes")
    ax.set_xlabel("collision")
    ax.set_ylabel("divergence from the truth")
    ax.set_title("particle %d" % summary["particle"])
    ax.grid(True, which="major")
    legend_below(fig, (ax,))
    caption = ("Divergence of particle %d's trajectory in each tier from the truth (MPFR, %d bits) per collision: the "
               "largest of |dt|, |dq|, |dv|; grey: MUPO phases; dashed: the tolerance %g. The horizon (the first "
               "collision past it): %s." % (summary["particle"], summary["truth"]["bits"], summary["tolerance"],
                                            ", ".join(horizons)))
    return [Drawing("shadow", fig, caption)]


def draw(directory: PathLike, formats: object = ("png",)) -> list[str]:
    """Draw a shadow directory's shadow (``rotleak shadow --out DIR``) in each format; returns the paths."""
    return _draw(directory, formats)  # type: ignore[arg-type]
