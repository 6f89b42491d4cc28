"""A regimes directory (``rotleak regimes --out DIR``): its coarse scan drawn as any scan (in coarse/), and regimes:
every probe (coarse and bisection) as alpha, or its upper bound, against omega, coloured by regime, with the
boundaries found and the predicted omega_sweep."""
from __future__ import annotations

import json
import os
from typing import Any

import matplotlib.pyplot as plt

from ..readers import PathLike
from . import ONE_COLUMN, Drawing, decades, legend_below, scan, styled
from . import draw as _draw
from .scan import REGIME_COLOURS, value_of


def probes(directory: str) -> list[tuple[float, dict[str, Any], str]]:
    """(omega, point of scan.json, where) for every probe: the coarse scan's points and the bisections'."""
    out = []
    for sub in ("coarse", "low_mid", "mid_high"):
        base = os.path.join(directory, sub)
        if not os.path.isdir(base):
            continue
        scans = [base] if sub == "coarse" else [os.path.join(base, d) for d in sorted(os.listdir(base))]
        for s in scans:
            path = os.path.join(s, "scan.json")
            if not os.path.exists(path):
                continue
            with open(path) as f:
                for p in json.load(f)["points"]:
                    x = value_of(p["values"].get("leak.omega", ""))
                    if x is not None and x > 0:
                        out.append((x, p, sub))
    return out


@styled
def probes_figure(directory: str, doc: dict[str, Any]) -> Drawing:
    """regimes: every probe's alpha or bound against omega, coloured by regime, the boundaries shaded."""
    fig, ax = plt.subplots(figsize=(ONE_COLUMN, 2.9))
    ys: list[float] = []
    seen = set()
    for x, p, sub in probes(directory):
        a = p["alpha"]
        y, marker = (a["value"], "o") if a["value"] is not None else (a["upper_bound"], "v")
        if y is None:
            continue
        ys.append(y)
        seen.add(p["tail"]["regime"])
        ax.scatter([x], [y], marker=marker, s=22 if sub == "coarse" else 9,
                   color=REGIME_COLOURS.get(p["tail"]["regime"], "k"))
    for name, colour in REGIME_COLOURS.items():
        if name in seen:
            ax.scatter([], [], marker="s", color=colour, label=name)
    notes = []
    for key, b in (doc.get("boundaries") or {}).items():
        if b:
            unplaced = b.get("unplaced") is not None  # only bracketed: a probe inside was undecided
            ax.axvspan(b["lo"], b["hi"], color="k", alpha=0.12, lw=0, hatch="//" if unplaced else None)
            ax.text(b["hi"], 1, " " + key.replace("_", "/"), transform=ax.get_xaxis_transform(), va="top")
            notes.append("%s in [%.3g, %.3g]%s" % (key.replace("_", "/"), b["lo"], b["hi"],
                                                   " (not placed: hatched)" if unplaced else ""))
    sweep = (doc.get("predicted") or {}).get("omega_sweep")
    if sweep:
        ax.axvline(sweep, color="k", ls=":", lw=0.8, label="omega_sweep")
    ax.set_xscale("log")
    ax.set_yscale("log")
    decades(ax, ys)
    ax.set_xlabel("omega")
    ax.set_ylabel("alpha")
    ax.set_title("regimes against omega")
    ax.grid(True, which="major")
    legend_below(fig, (ax,))
    caption = ("alpha of every probe against omega (circles: measured; triangles: upper bounds; large: the coarse "
               "scan, small: bisection), coloured by the tail's regime; grey: the boundaries found%s%s." % (
                   " (" + "; ".join(notes) + ")" if notes else " (none)",
                   "; dotted: the predicted omega_sweep = %.3g" % sweep if sweep else ""))
    return Drawing("regimes", fig, caption)


def figures(where: PathLike) -> list[Drawing]:
    """A regimes search's pictures: its coarse scan's (named coarse/NAME) and regimes."""
    directory = os.fspath(where)
    with open(os.path.join(directory, "regimes.json")) as f:
        doc = json.load(f)
    coarse = os.path.join(directory, "coarse")
    drew = [d._replace(name="coarse/" + d.name) for d in scan.figures(coarse)] if os.path.exists(
        os.path.join(coarse, "scan.json")) else []
    return drew + [probes_figure(directory, doc)]


def draw(where: PathLike, formats: object = ("png",)) -> list[str]:
    """Draw a regimes search (``rotleak regimes --out DIR``): its coarse scan's pictures and regimes, in each format.

    Returns
    -------
    list of str
        The paths drawn.
    """
    return _draw(where, formats)  # type: ignore[arg-type]
