"""A run directory (``rotleak simulate``): survival (P(t) log-log and semi-log with the error band, the kappa fit and
the alpha crossing, and t P(t) with the tail amplitude C; the range past ``unresolved_from`` greyed and the axes
clipped to what is resolved) and, when fc.csv exists, fc (the collision density per time window, the table's
straight edges and arcs marked)."""
from __future__ import annotations

import math
from typing import Any, Optional, Union

import matplotlib.pyplot as plt
from matplotlib import ticker

from ..readers import PathLike, Run, read_run
from . import FIT, LEAK, MEASURED, MODEL, TWO_COLUMN, Drawing, exact_text, legend_below, mask_unresolved, styled
from . import draw as _draw


def unresolved_from(summary: dict[str, Any]) -> Optional[float]:
    """The first time P is a bound, not a measurement (a split run's allowance for lines not drawn); None when every
    time is resolved."""
    allowance = (summary.get("splitting") or {}).get("unsplit_allowance") or {}
    t = allowance.get("unresolved_from")
    return float(t) if t is not None else None


def scene_text(summary: dict[str, Any]) -> str:
    """The scene in a caption: the stadium, the leak and the sample."""
    sc = summary["scene"]
    split = summary.get("splitting")
    scheme = summary.get("sampling", {}).get("scheme", "uniform")
    if "stadium" in sc:
        where = "stadium d = %s, r = %s" % (sc["stadium"]["d"], sc["stadium"]["r"])
    else:  # any other table (docs/tables.md): its kind and parameters as written
        where = "%s %s" % (sc["table"]["kind"], ", ".join("%s = %s" % (k, v) for k, v in sc["table"].items()
                                                          if k not in ("kind", "vertices")))
    leaks = [sc["leak"]] if "leak" in sc else sc["leaks"]
    leak_text = "; ".join("leak%s at s_L = %s, width %s, omega = %s" % (
        " on loop %d" % leak["loop"] if leak.get("loop") else "", leak["start"], leak["width"], leak["omega"])
        for leak in leaks)
    return ("%s; %s; %s %s (%s%s), %s tier"
            % (where.strip(), leak_text, format(summary["particles"], ","),
               "lines" if split else "particles", scheme, ", split every %g" % split["split_every"] if split else "",
               summary["tier"]))


def fits_text(summary: dict[str, Any]) -> str:
    """kappa, alpha and C as a caption says them."""
    kappa, alpha = summary["kappa"], summary["alpha"]
    parts = []
    if kappa["value"] is not None:
        parts.append("kappa = %.5g +- %.2g on t in [%g, %g] (dashed)" % (kappa["value"], kappa["error"],
                                                                         *kappa["window"]))
    if alpha["value"] is not None:
        parts.append("alpha = %.3g where P is %g x the fit (dot, t = %.4g)" % (alpha["value"], alpha.get("factor", 10),
                                                                              alpha["crossing_time"]))
    elif alpha.get("upper_bound") is not None:
        parts.append("alpha < %.3g (no tail resolved)" % alpha["upper_bound"])
    amp = summary["tail"].get("amplitude") or {}
    if amp.get("value") is not None:
        parts.append("C = %.3g +- %.2g +- %.2g (syst.) on t in [%g, %g]" % (amp["value"], amp["error"],
                                                                          amp["systematic"], amp["from"], amp["to"]))
    return "; ".join(parts)


@styled
def survival_figure(run: Run) -> Drawing:
    """survival: (a) P(t) log-log, (b) semi-log with the fits, (c) t P(t) with C and the covering model's C."""
    summary = run.summary
    alive = run.survival[(run.survival["survivors"] > 0) & (run.survival["P"] > 0)]
    alive = alive[alive["t"] <= min(float(run.survival["t"].iloc[-1]), 1.25 * (unresolved_from(summary) or math.inf))]
    t, P = alive["t"].astype(float).tolist(), alive["P"].astype(float).tolist()
    err: Optional[list[float]] = alive["P_err"].astype(float).tolist() if "P_err" in alive else None
    cut = unresolved_from(summary)
    # the axes end a little past where P stops being resolved: the grey strip shows where, not a page of grey
    t_end = min(float(run.survival["t"].iloc[-1]), 1.25 * cut if cut is not None else math.inf)
    kept = [i for i, x in enumerate(t) if cut is None or x < cut]  # resolved: what sets the axes
    kappa, alpha = summary["kappa"], summary["alpha"]
    fig, axes = plt.subplots(1, 3, figsize=(TWO_COLUMN, 2.5))
    ax1, ax2, ax3 = axes
    floor = min(P[i] for i in kept) / 3 if kept else None
    for ax in (ax1, ax2):
        mask_unresolved(ax, cut, t_end)
        ax.plot(t, P, color=MEASURED, label="P(t)")
        if err is not None:  # one standard error either side, where it stays below P
            ax.fill_between(t, [max(p - e, p * 1e-3) for p, e in zip(P, err)], [p + e for p, e in zip(P, err)],
                            alpha=0.25, lw=0, color=MEASURED)
        if kappa["value"] is not None:
            k, lna = kappa["value"], kappa["log_amplitude"]
            lowest = floor if floor is not None else min(P)
            tt = [x for x in t if math.exp(lna - k * x) * alpha.get("factor", 10) >= lowest]
            ax.plot(tt, [math.exp(lna - k * x) for x in tt], "--", color=FIT, lw=0.8, label="exp. fit")
        if alpha["value"] is not None:
            ax.plot([alpha["crossing_time"]], [alpha["value"]], "o", color=FIT, label="alpha")
        ax.set_yscale("log")
        if floor is not None:
            ax.set_ylim(bottom=floor, top=1.5)
        ax.set_xlabel("t")
        ax.grid(True, which="major")
    ax1.set_xscale("log")
    ax1.set_xlim(left=1, right=t_end)
    ax2.set_xlim(0, t_end)
    ax2.xaxis.set_major_locator(ticker.MaxNLocator(4))  # five-digit times: few ticks, or their labels run together
    ax1.set_ylabel("P(t)")
    ax1.set_title("(a) P(t)")
    ax2.set_title("(b) semi-log")
    # t P(t): flat where P ~ C / t; the amplitude C over the stretch it was measured on
    mask_unresolved(ax3, cut, t_end)
    ax3.plot(t, [x * p for x, p in zip(t, P)], color=MEASURED)
    if err is not None:
        ax3.fill_between(t, [x * max(p - e, p * 1e-3) for x, p, e in zip(t, P, err)],
                         [x * (p + e) for x, p, e in zip(t, P, err)], alpha=0.25, lw=0, color=MEASURED)
    amp: dict[str, Any] = summary["tail"].get("amplitude") or {}
    if amp.get("value") is not None:
        c, e = amp["value"], math.hypot(amp["error"], amp["systematic"])
        ax3.plot([amp["from"], amp["to"]], [c, c], color=FIT, lw=1.2, label="C")
        ax3.fill_between([amp["from"], amp["to"]], [c - e] * 2, [c + e] * 2, color=FIT, alpha=0.25, lw=0)
    model = (summary.get("predicted") or {}).get("tail")
    if model and model.get("forms") and model.get("crossing"):  # docs/model.md "Predicting the tail from omega"
        c, e = model["amplitude"], model["amplitude_error"]
        curve = model.get("curve") or [[model["crossing"], c], [t_end, c]]  # off a rational: its sweep
        ct, cy = [x for x, _ in curve if x <= t_end], [y for x, y in curve if x <= t_end]
        ax3.plot(ct, cy, color=MODEL, lw=1, ls="-.", label="model C")
        ax3.fill_between(ct, [y * (1 - e / c) for y in cy], [y * (1 + e / c) for y in cy], color=MODEL, alpha=0.12,
                         lw=0)
        if model.get("end") is not None and model["end"] < t_end:
            ax3.axvline(model["end"], color=MODEL, lw=0.8, ls=":")
    ax3.set_xscale("log")
    ax3.set_yscale("log")
    tp = [t[i] * P[i] for i in kept if t[i] >= 10]
    if tp:  # four decades below the highest t P: a tail's plateau, not the collapse after it
        ax3.set_ylim(bottom=max(tp) * 1e-4, top=max(tp) * 3)
    ax3.set_xlim(left=1, right=t_end)
    ax3.set_xlabel("t")
    ax3.set_ylabel("t P(t)")
    ax3.set_title("(c) t P(t)")
    ax3.grid(True, which="major")
    legend_below(fig, axes)
    caption = "P(t) of %s. %s." % (scene_text(summary), fits_text(summary) or "no fit")
    if cut is not None:
        caption += " Grey: t >= %g, where P is a bound (allowance for lines not drawn), not a measurement." % cut
    if model and model.get("forms") and model.get("crossing"):
        caption += " Dash-dot: the covering model's C = %.3g +- %.2g (2 r omega near %s)." % (
            model["amplitude"], model["amplitude_error"], model["rational"])
    return Drawing("survival", fig, caption)


def pieces(stadium: dict[str, Any]) -> Optional[list[tuple[float, float, str]]]:
    """The stadium's pieces in s (docs/model.md "The billiard"): (from, to, "straight" or "arc") from the top edge's
    midpoint clockwise; None when d or r has no rational value to draw with."""
    d, r = exact_text(stadium["d"]), exact_text(stadium["r"])
    if d is None or r is None:
        return None
    length = 2 * d + 2 * math.pi * r
    j = [d / 2 / length]
    for step in (math.pi * r, d, math.pi * r):
        j.append(j[-1] + step / length)
    return [(0.0, j[0], "straight"), (j[0], j[1], "arc"), (j[1], j[2], "straight"), (j[2], j[3], "arc"),
            (j[3], 1.0, "straight")]


@styled
def density_figure(run: Run) -> Optional[Drawing]:
    """fc: f_c(s) per time window, the stadium's arcs shaded and the leak marked where it stands still."""
    fc = run.fc
    if fc is None:
        return None
    summary = run.summary
    s = fc["s"].astype(float).tolist()
    fig, ax = plt.subplots(figsize=(TWO_COLUMN, 2.4))
    scene = summary["scene"]
    parts = pieces(scene["stadium"]) or [] if "stadium" in scene else []
    for piece in parts:
        if piece[2] == "arc":
            ax.axvspan(piece[0], piece[1], color="0.93", lw=0, zorder=0)
    if parts:  # the pieces named along the top: top edge (both ends of s), right arc, bottom edge, left arc
        top = ax.secondary_xaxis("top")
        top.set_xticks([(a + b) / 2 for a, b, _ in parts[1:4]] + [0.0, 1.0],
                       ["right arc", "bottom edge", "left arc", "top edge", "top edge"])
        top.tick_params(length=0)
    if parts:  # the shading's legend entry only where there are arcs to shade
        ax.plot([], [], color="0.85", lw=6, label="arcs")
    columns = [c for c in fc.columns if c.startswith("fc")]  # fc[from,to]; count[from,to] beside each
    for k, column in enumerate(columns):
        ax.plot(s, fc[column].astype(float).tolist(), lw=0.8, color="C%d" % ((k + 4) % 10) if k else "C0",
                label=column.replace("fc", "t in "))
    # the leaks that stand still, where s is their loop's own (a table of one loop; several loops are laid end to
    # end in f_c's s, docs/tables.md)
    one_loop = "stadium" in scene or summary.get("table", {}).get("loops", 1) == 1
    leaks = [scene["leak"]] if "leak" in scene else scene["leaks"]
    stationary = one_loop and all(leak["omega"] == "0" for leak in leaks)
    for leak in leaks if stationary else []:
        start, width = exact_text(leak["start"]), exact_text(leak["width"])
        if start is None or width is None:
            stationary = False
            continue
        for shift in (-1, 0, 1):  # the leak on the circle s mod 1
            ax.axvspan(start - width / 2 + shift, start + width / 2 + shift, color=LEAK, alpha=0.3, lw=0)
    if stationary:
        ax.plot([], [], color=LEAK, alpha=0.4, lw=6, label="leak" if len(leaks) == 1 else "leaks")
    ax.set_xlim(0, 1)
    ax.set_xlabel("s")
    ax.set_ylabel("f_c(s)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), borderaxespad=0)  # beside the axes: it hides no spike
    ax.grid(True)
    fig.tight_layout(pad=0.3)
    shading = ("Shaded: the arcs (the rest is the straight edges)" if parts else
               "s: the share of the whole boundary, its loops laid end to end (docs/tables.md)")
    caption = ("f_c(s), the collisions per unit s in each time window, of %s. %s%s." % (
        scene_text(summary), shading, "; red: the leak" if stationary else
        "; the leak moves (or lies on another loop), so it is not drawn"))
    return Drawing("fc", fig, caption)


def figures(run: Union[Run, PathLike]) -> list[Drawing]:
    """survival and, where the run has f_c, fc (a directory is read first: a damaged one is RotleakError)."""
    if not isinstance(run, Run):
        run = read_run(run)
    drew = [survival_figure(run), density_figure(run)]
    return [d for d in drew if d is not None]


def draw(run: Union[Run, PathLike], out: Optional[PathLike] = None, formats: Any = ("png",)) -> list[str]:
    """Draw a run's survival and, where it has f_c, fc, saved in each format.

    Parameters
    ----------
    run : Run or a run directory
        A directory is read first (a damaged one is refused with the reason ``rotleak fit`` gives,
        RotleakError).
    out : directory, optional
        Where the pictures go; by default the run's own directory (required for a run made in process).
    formats : str or list of str, default ("png",)
        png, pdf, svg.

    Returns
    -------
    list of str
        The paths drawn.
    """
    return _draw(run if isinstance(run, Run) else read_run(run), formats, out)

