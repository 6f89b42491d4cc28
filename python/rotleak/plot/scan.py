"""A scan directory: scan_survival (every point's P(t), log-log and semi-log, each to where it is resolved, coloured in
the order of the swept values), and per swept key scan_<key> (kappa and alpha against the key at its exact value
rounded once, every point in order, bounds drawn as black triangles, log axes where the key spans decades) with the
regime of each point as a coloured strip along the key, and the predicted omega_sweep marked when the key is
leak.omega; scan_alpha_covering: alpha against the zero measure of each point's MUPO covering f_L."""
from __future__ import annotations

import math
from typing import Any, Optional, Union

import matplotlib.pyplot as plt
from matplotlib import ticker

from ..readers import PathLike, Scan, read_scan
from . import (BOUND, MEASURED, ONE_COLUMN, TWO_COLUMN, Drawing, decades, exact_text, label_points, legend_below,
               styled)
from . import draw as _draw
from .run import unresolved_from

#: The regimes' own colours, none of them a colour that means something else in these pictures (blue: measured,
#: black: a bound).
REGIME_COLOURS = {"stationary": "0.6", "low": "C9", "mid": "C8", "high": "C6", "undecided": "C4",
                  "near-rational": "C5"}


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


def point_label(point: dict[str, Any]) -> str:
    """A point's swept values, short: "omega = 2/3, width = 0.01"."""
    return ", ".join("%s = %s" % (key.split(".")[-1], v) for key, v in point["values"].items())


@styled
def curves(scan: Scan) -> Drawing:
    """scan_survival: every point's P(t), each drawn to where it is resolved, in the order of the first swept key."""
    doc = scan.document
    key = doc["axes"][0]["key"]
    ordered = [p for _, p in points_along(doc, key)]
    ordered += [p for p in doc["points"] if p not in ordered]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(TWO_COLUMN, 2.6))
    colours = plt.get_cmap("viridis")
    floor = math.inf
    t_end = 0.0
    cut_any = False
    for k, point in enumerate(ordered):
        run = scan.point(point["point"])
        cut = unresolved_from(run.summary)
        cut_any = cut_any or cut is not None
        curve = run.survival[(run.survival["survivors"] > 0) & (run.survival["t"] > 0) & (run.survival["P"] > 0)]
        if cut is not None:
            curve = curve[curve["t"] < cut]  # a bound past it: not drawn
        t, P = curve["t"].astype(float).tolist(), curve["P"].astype(float).tolist()
        if not P:
            continue
        floor, t_end = min(floor, min(P)), max(t_end, t[-1])
        colour = colours(k / max(len(ordered) - 1, 1) * 0.9)
        for ax in (ax1, ax2):
            ax.plot(t, P, lw=0.9, color=colour, label=point_label(point))
    for ax, title in ((ax1, "(a) P(t)"), (ax2, "(b) semi-log")):
        ax.set_yscale("log")
        ax.set_xlabel("t")
        ax.set_title(title)
        ax.grid(True, which="major")
        if floor < math.inf:
            ax.set_ylim(bottom=floor / 3, top=1.5)
    ax1.set_ylabel("P(t)")
    ax1.set_xscale("log")
    ax1.set_xlim(left=1)
    if t_end:
        ax2.set_xlim(0, t_end)
    ax2.xaxis.set_major_locator(ticker.MaxNLocator(4))  # five-digit times: few ticks, or their labels run together
    legend_below(fig, (ax1,))
    keys = ", ".join(a["key"] for a in doc["axes"])
    caption = ("P(t) of the %d points of the scan over %s (particles a point: %s), coloured in the order of %s; "
               "each drawn while it has survivors%s." % (
                   len(doc["points"]), keys, "/".join(sorted({format(p["particles"], ",") for p in doc["points"]})),
                   key, ", up to where a split run's P becomes a bound" if cut_any else ""))
    return Drawing("scan_survival", fig, caption)


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


@styled
def against_key(doc: dict[str, Any], key: str) -> Optional[Drawing]:
    """scan_<key>: kappa, alpha (or its bound) and the regime against one swept key, every point at its exact value
    rounded once, in order; None where the key has no value to draw."""
    pts = points_along(doc, key)
    if not pts:
        return None
    xs = [x for x, _ in pts]
    positive = [x for x in xs if x > 0]
    # log where the values span decades; a 0 among them (a stationary point) stays on the axis through a
    # linear stretch below the smallest positive value (symlog)
    logx = bool(positive) and min(xs) >= 0 and max(positive) / min(positive) >= 30
    fig, (ax_k, ax_a, ax_r) = plt.subplots(3, 1, figsize=(ONE_COLUMN, 4.4), sharex=True,
                                           gridspec_kw={"height_ratios": [3, 3, 0.7]})
    kx = [(x, p["kappa"]) for x, p in pts if p["kappa"]["value"] is not None]
    ax_k.errorbar([x for x, _ in kx], [k["value"] for _, k in kx], yerr=[k["error"] for _, k in kx], fmt="o-",
                  color=MEASURED, lw=0.8)
    ax_k.set_ylabel("kappa")
    ax_k.grid(True, which="major")
    val = [(x, p["alpha"]) for x, p in pts if p["alpha"]["value"] is not None]
    bnd = [(x, p["alpha"]) for x, p in pts if p["alpha"]["value"] is None and p["alpha"]["upper_bound"] is not None]
    if val:
        ax_a.errorbar([x for x, _ in val], [a["value"] for _, a in val], yerr=[a["error"] for _, a in val], fmt="o",
                      color=MEASURED, label="alpha")
    if bnd:
        ax_a.scatter([x for x, _ in bnd], [a["upper_bound"] for _, a in bnd], marker="v", s=14, color=BOUND,
                     label="upper bound")
    ax_a.set_yscale("log")
    ax_a.set_ylabel("alpha")
    ax_a.grid(True, which="major")
    for x, p in pts:  # the regime strip
        ax_r.scatter([x], [0], marker="s", s=40, color=REGIME_COLOURS.get(p["tail"]["regime"], "k"))
    seen = {p["tail"]["regime"] for _, p in pts}
    for name, colour in REGIME_COLOURS.items():
        if name in seen:  # the key lists the regimes this scan has
            ax_r.scatter([], [], marker="s", color=colour, label=name)
    ax_r.set_yticks([])
    ax_r.set_ylabel("regime", rotation=0, ha="right", va="center")
    sweep = doc["points"][0]["predicted"]["omega_sweep"]
    marked = key == "leak.omega" and min(xs) / 2 <= sweep <= max(xs) * 2  # only where it is on the axis
    if marked:
        for ax in (ax_k, ax_a, ax_r):
            ax.axvline(sweep, color="k", ls=":", lw=0.8, label="omega_sweep" if ax is ax_r else None)
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
    ax_k.set_title("against %s" % key.split(".")[-1])
    decades(ax_a, [a["value"] for _, a in val] + [a["upper_bound"] for _, a in bnd])
    legend_below(fig, (ax_a, ax_r))
    particles = sorted({p["particles"] for _, p in pts})
    caption = ("kappa (top), alpha (middle; black triangles: upper bounds where no tail is resolved) and the tail's "
               "regime (bottom) of the %d points against %s, each at its exact value rounded once; %s particles a "
               "point%s." % (len(pts), key, "/".join(format(n, ",") for n in particles),
                             "; dotted: omega_sweep = lambda / 2r = %.3g" % sweep if marked else ""))
    return Drawing("scan_%s" % key.replace(".", "_"), fig, caption)


@styled
def against_covering(doc: dict[str, Any]) -> Optional[Drawing]:
    """scan_alpha_covering: alpha (values and bounds) against the MUPO covering's zero measure of each point's
    omega; None where the points' coverings do not differ."""
    pts = [p for p in doc["points"] if p.get("number_theory")]
    if len({p["number_theory"]["covering_zero_measure"] for p in pts}) < 2:
        return None
    fig, ax = plt.subplots(figsize=(ONE_COLUMN, 2.8))
    labels: list[tuple[float, float, str]] = []
    ys: list[float] = []
    for p in sorted(pts, key=lambda q: q["number_theory"]["covering_zero_measure"]):
        x = p["number_theory"]["covering_zero_measure"]
        label = ", ".join(p["values"].values())
        y = p["alpha"]["value"] if p["alpha"]["value"] is not None else p["alpha"]["upper_bound"]
        if y is None:
            continue
        if p["alpha"]["value"] is not None:
            ax.errorbar([x], [y], yerr=[p["alpha"]["error"]], fmt="o", color=MEASURED)
        else:
            ax.scatter([x], [y], marker="v", s=14, color=BOUND)
        labels.append((x, y, label))
        ys.append(y)
    ax.set_yscale("log")
    decades(ax, ys)
    ax.set_xlim(-0.05, 1.05)
    ax.yaxis.set_minor_formatter(ticker.NullFormatter())  # minor labels overlapped on short log axes
    ax.set_xlabel("zero measure of f_L")
    ax.set_ylabel("alpha")
    ax.set_title("alpha against the covering")
    ax.grid(True, which="major")
    fig.tight_layout(pad=0.3)
    label_points(ax, labels)  # placed once the layout is final
    caption = ("alpha (black triangles: upper bounds) of each point against the zero measure of its omega's MUPO "
               "covering f_L at delta = %s." % pts[0]["number_theory"]["covering_delta"])
    return Drawing("scan_alpha_covering", fig, caption)


def figures(scan: Union[Scan, PathLike]) -> list[Drawing]:
    """scan_survival, scan_<key> for each swept key, scan_alpha_covering (a directory is read first; a damaged scan
    is refused: RotleakError)."""
    if not isinstance(scan, Scan):
        scan = read_scan(scan)
    scan.table  # noqa: B018 -- read and checked against scan.json before anything is drawn
    doc = scan.document
    drew = [curves(scan)] + [against_key(doc, axis["key"]) for axis in doc["axes"]] + [against_covering(doc)]
    return [d for d in drew if d is not None]


def draw(scan: Union[Scan, PathLike], formats: Any = ("png",)) -> list[str]:
    """Draw a scan's pictures beside its files, in each format (png, pdf, svg); returns the paths."""
    return _draw(scan if isinstance(scan, Scan) else read_scan(scan), formats)
