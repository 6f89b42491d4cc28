"""A regimes directory (``rotleak regimes --out DIR``): its coarse scan drawn as any scan, and
regimes.png: every probe (coarse and bisection) as alpha, or its upper bound, against omega, coloured
by regime, with the boundaries found and the predicted omega_sweep."""
from __future__ import annotations

import json
import math
import os
from typing import Any

from ..readers import PathLike

import matplotlib.pyplot as plt

from . import save, scan
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


def draw(where: PathLike) -> list[str]:
    """Draw a regimes search (``rotleak regimes --out DIR``): its coarse scan's pictures and regimes.png.

    Returns
    -------
    list of str
        The paths drawn.
    """
    directory = os.fspath(where)
    with open(os.path.join(directory, "regimes.json")) as f:
        doc = json.load(f)
    drew = scan.draw(os.path.join(directory, "coarse")) if os.path.exists(
        os.path.join(directory, "coarse", "scan.json")) else []
    fig, ax = plt.subplots(figsize=(9, 4.8))
    ys: list[float] = []
    for x, p, sub in probes(directory):
        a = p["alpha"]
        y, marker = (a["value"], "o") if a["value"] is not None else (a["upper_bound"], "v")
        if y is None:
            continue
        ys.append(y)
        ax.scatter([x], [y], marker=marker, s=36 if sub == "coarse" else 18,
                   color=REGIME_COLOURS.get(p["tail"]["regime"], "k"))
    for name, colour in REGIME_COLOURS.items():
        ax.scatter([], [], marker="s", color=colour, label=name)
    for key, b in (doc.get("boundaries") or {}).items():
        if b:
            unplaced = b.get("unplaced") is not None  # only bracketed: a probe inside was undecided
            ax.axvspan(b["lo"], b["hi"], color="k", alpha=0.12, lw=0, hatch="//" if unplaced else None)
            ax.text(b["hi"], 1, " " + key.replace("_", "/") + (" (not placed)" if unplaced else ""),
                    transform=ax.get_xaxis_transform(), fontsize=8, va="top")
    sweep = (doc.get("predicted") or {}).get("omega_sweep")
    if sweep:
        ax.axvline(sweep, color="k", ls=":", lw=1, label="omega_sweep")
    ax.set_xscale("log")
    ax.set_yscale("log")
    if ys:  # whole decades, at least two, so the axis has ticks to read (it once had one)
        lo, hi = 10 ** math.floor(math.log10(min(ys))), 10 ** math.ceil(math.log10(max(ys)))
        if hi / lo < 100:  # one decade or none: a decade more below, and above too when there was none
            hi = hi * 10 if hi == lo else hi
            lo = lo / 10
        ax.set_ylim(lo, hi)
    ax.set_xlabel("omega")
    ax.set_ylabel("alpha (triangles: upper bounds)")
    ax.set_title("regimes: coarse probes (large) and bisection probes (small); grey: boundaries")
    ax.legend(fontsize=7, ncol=3)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(directory, "regimes.png")
    save(fig, path)
    return drew + [path]
