"""A scan directory: scan_survival.png (every point's P(t), log-log and semi-log, error bands where the
run has them), and per swept key scan_<key>.png (kappa and alpha against the key, bounds drawn as
downward arrows, log axes where the key spans decades) with the regime of each point as a coloured
strip along the key, and the predicted omega_sweep marked when the key is leak.omega;
scan_alpha_covering.png: alpha against the zero measure of each point's MUPO covering f_L."""
from __future__ import annotations

import math
import os
from typing import Any, Optional, Union

import matplotlib.pyplot as plt
from matplotlib import ticker

from ..readers import PathLike, Scan, read_scan
from . import Point, annotate_clear, exact_text, save

REGIME_COLOURS = {"stationary": "0.5", "low": "C0", "mid": "C2", "high": "C3", "undecided": "C4",
                  "near-rational": "C1"}


def value_of(text: str) -> Optional[float]:
    """A swept value as a float for drawing ("2/3", "1e-4") where scan.json has no number for it (a scan written
    before it recorded them); an expression is None there."""
    v = exact_text(text)
    if v is None:
        try:
            v = float(text)
        except ValueError:
            return None
    return v


def curves(scan: Scan) -> str:
    """scan_survival.png: every point's P(t) with its error band; returns its path."""
    doc = scan.document
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5))
    for k, point in enumerate(doc["points"]):
        curve = scan.point(point["point"]).survival
        curve = curve[(curve["survivors"] > 0) & (curve["t"] > 0)]
        t, P = curve["t"].astype(float).tolist(), curve["P"].astype(float).tolist()
        label = ", ".join("%s = %s" % (key.split(".")[-1], v) for key, v in point["values"].items())
        for ax in (ax1, ax2):
            ax.plot(t, P, lw=1, color="C%d" % (k % 10), label=label)
            if "P_err" in curve:
                e = curve["P_err"].astype(float).tolist()
                ax.fill_between(t, [max(p - s, p * 1e-3) for p, s in zip(P, e)], [p + s for p, s in zip(P, e)],
                                color="C%d" % (k % 10), alpha=0.2, lw=0)
    for ax, title in ((ax1, "log-log"), (ax2, "semi-log")):
        ax.set_yscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("P(t)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    ax1.set_xscale("log")
    ax2.legend(fontsize=7, ncol=2)
    keys = ", ".join(a["key"] for a in doc["axes"])
    fig.suptitle("P(t) of every point of the scan over %s (%d points)" % (keys, len(doc["points"])))
    fig.tight_layout()
    path = os.path.join(scan.path, "scan_survival.png")
    save(fig, path)
    return path


def points_along(doc: dict[str, Any], key: str) -> list[tuple[float, dict[str, Any]]]:
    """The points with a number for `key`, in increasing order of it: scan.json's `numbers` (each value, an
    expression too, evaluated exactly and rounded once), else the value read as a plain number."""
    pts: list[tuple[float, dict[str, Any]]] = []
    for point in doc["points"]:
        x = point.get("numbers", {}).get(key)
        if x is None:
            x = value_of(point["values"][key])
        if x is not None:
            pts.append((float(x), point))
    return sorted(pts, key=lambda xp: xp[0])


def against_key(scan_dir: str, doc: dict[str, Any], key: str) -> Optional[str]:
    """scan_<key>.png: kappa, alpha (or its bound) and the regime against one swept key; None where the key
    has no value to draw."""
    pts = points_along(doc, key)
    if not pts:
        return None
    xs = [x for x, _ in pts]
    positive = [x for x in xs if x > 0]
    # log where the values span decades; a 0 among them (a stationary point) stays on the axis through a
    # linear stretch below the smallest positive value (symlog)
    logx = bool(positive) and min(xs) >= 0 and max(positive) / min(positive) >= 30
    fig, (ax_k, ax_a, ax_r) = plt.subplots(3, 1, figsize=(8, 8), sharex=True,
                                           gridspec_kw={"height_ratios": [3, 3, 0.6]})
    kx = [(x, p["kappa"]) for x, p in pts if p["kappa"]["value"] is not None]
    ax_k.errorbar([x for x, _ in kx], [k["value"] for _, k in kx], yerr=[k["error"] for _, k in kx], fmt="o-", ms=4)
    ax_k.set_ylabel("kappa")
    ax_k.grid(True, which="both", alpha=0.3)
    val = [(x, p["alpha"]) for x, p in pts if p["alpha"]["value"] is not None]
    bnd = [(x, p["alpha"]) for x, p in pts if p["alpha"]["value"] is None and p["alpha"]["upper_bound"] is not None]
    if val:
        ax_a.errorbar([x for x, _ in val], [a["value"] for _, a in val], yerr=[a["error"] for _, a in val], fmt="o",
                      ms=4, label="alpha")
    if bnd:
        # black: a colour of its own (orange is the near-rational regime below)
        ax_a.scatter([x for x, _ in bnd], [a["upper_bound"] for _, a in bnd], marker="v", color="k",
                     label="upper bound (no tail resolved)")
    ax_a.set_yscale("log")
    ax_a.set_ylabel("alpha")
    ax_a.grid(True, which="both", alpha=0.3)
    ax_a.legend(fontsize=8)
    for x, p in pts:  # the regime strip
        ax_r.scatter([x], [0], marker="s", s=120, color=REGIME_COLOURS.get(p["tail"]["regime"], "k"))
    for name, colour in REGIME_COLOURS.items():
        ax_r.scatter([], [], marker="s", color=colour, label=name)
    ax_r.set_yticks([])
    ax_r.set_ylabel("regime", rotation=0, ha="right", va="center", fontsize=8)
    handles, labels = ax_r.get_legend_handles_labels()
    sweep = doc["points"][0]["predicted"]["omega_sweep"]
    if key == "leak.omega" and min(xs) / 2 <= sweep <= max(xs) * 2:  # only where it is on the axis
        for ax in (ax_k, ax_a, ax_r):
            ax.axvline(sweep, color="k", ls=":", lw=1)
        ax_a.text(sweep, ax_a.get_ylim()[1], " omega_sweep", fontsize=7, va="top")
    if logx and min(xs) > 0:
        ax_r.set_xscale("log")
    elif logx:
        ax_r.set_xscale("symlog", linthresh=min(positive) / 2, linscale=0.5)
        ax_r.set_xlim(-min(positive) / 4, max(positive) * 2)  # 0 and the positive side only
        # 0, then whole decades from the smallest positive value (a decade inside the linear stretch overlapped 0)
        ax_r.set_xticks([0] + [10.0 ** k for k in range(math.ceil(math.log10(min(positive)) - 1e-9),
                                                          math.floor(math.log10(max(positive)) + 1e-9) + 1)])
        ax_r.xaxis.set_minor_locator(ticker.NullLocator())
    ax_r.set_xlabel(key)
    particles = sorted({p["particles"] for _, p in pts})
    fig.suptitle("kappa, alpha and regime against %s (%s particles a point)"
                 % (key, "/".join("%g" % n for n in particles)))
    # the regimes' key below the x label, in space kept for it (it once covered the label)
    fig.legend(handles, labels, fontsize=7, ncol=len(labels), loc="lower center", frameon=False)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    name = "scan_%s.png" % key.replace(".", "_")
    save(fig, os.path.join(scan_dir, name))
    return name


def against_covering(scan_dir: str, doc: dict[str, Any]) -> Optional[str]:
    """alpha (values and bounds) against the MUPO covering's zero measure of each point's omega."""
    pts = [p for p in doc["points"] if p.get("number_theory")]
    if len({p["number_theory"]["covering_zero_measure"] for p in pts}) < 2:
        return None
    fig, ax = plt.subplots(figsize=(7, 4.5))
    placed: list[Point] = []  # points labelled so far: a neighbour's label steps aside (annotate_clear)
    for p in sorted(pts, key=lambda q: q["number_theory"]["covering_zero_measure"]):
        x = p["number_theory"]["covering_zero_measure"]
        label = ", ".join(p["values"].values())
        y = p["alpha"]["value"] if p["alpha"]["value"] is not None else p["alpha"]["upper_bound"]
        if y is None:
            continue
        if p["alpha"]["value"] is not None:
            ax.errorbar([x], [y], yerr=[p["alpha"]["error"]], fmt="o", color="C0", ms=4)
        else:
            ax.scatter([x], [y], marker="v", color="k")
        annotate_clear(ax, placed, label, (x, y), lambda q, p: abs(q[0] - p[0]) < 0.05 and
                       abs(math.log10(q[1] / p[1])) < 0.15, fontsize=7)
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(ticker.LogLocator(numticks=8))
    ax.yaxis.set_minor_formatter(ticker.NullFormatter())  # minor labels overlapped on short log axes
    ax.set_xlabel("zero measure of f_L (delta = %s)" % pts[0]["number_theory"]["covering_delta"])
    ax.set_ylabel("alpha (triangles: upper bounds)")
    ax.set_title("tail weight against the MUPO covering")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    save(fig, os.path.join(scan_dir, "scan_alpha_covering.png"))
    return "scan_alpha_covering.png"


def draw(scan: Union[Scan, PathLike]) -> list[str]:
    """Draw a scan's pictures beside its files.

    Parameters
    ----------
    scan : Scan or a scan directory
        A directory is read first (a damaged scan is refused: RotleakError).

    Returns
    -------
    list of str
        The paths drawn: scan_survival.png, scan_<key>.png per swept key, scan_alpha_covering.png.
    """
    if not isinstance(scan, Scan):
        scan = read_scan(scan)
    scan.table  # noqa: B018 -- read and checked against scan.json before anything is drawn
    doc, scan_dir = scan.document, scan.path
    drew = [os.path.basename(curves(scan))]
    for axis in doc["axes"]:
        name = against_key(scan_dir, doc, axis["key"])
        if name:
            drew.append(name)
    name = against_covering(scan_dir, doc)
    if name:
        drew.append(name)
    return [os.path.join(scan_dir, d) for d in drew]
