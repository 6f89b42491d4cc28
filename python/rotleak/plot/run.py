"""A run directory (``rotleak simulate``): survival.png (P(t) log-log and semi-log with the error
band, the kappa fit and the alpha crossing, and t P(t) with the tail amplitude C) and, when fc.csv exists, fc.png (collision density per
time window)."""
from __future__ import annotations

import math
import os
import textwrap
from typing import Any, Optional, Union

import matplotlib.pyplot as plt

from ..readers import PathLike, Run, read_run
from . import exact_text, save


def survival(run: Run, out: str) -> str:
    """Draws OUT/survival.png from the run's survival curve and fits; returns its path."""
    summary = run.summary
    alive = run.survival[run.survival["survivors"] > 0]
    t, P = alive["t"].astype(float).tolist(), alive["P"].astype(float).tolist()
    err: Optional[list[float]] = alive["P_err"].astype(float).tolist() if "P_err" in alive else None
    kappa, alpha = summary["kappa"], summary["alpha"]
    scheme = summary.get("sampling", {}).get("scheme", "uniform")
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(17, 4.5))
    for ax, loglog in ((ax1, True), (ax2, False)):
        split = summary.get("splitting")
        what = (", %s, split every %.4g" % (scheme, split["split_every"]) if split else
                "" if scheme == "uniform" else ", " + scheme)
        ax.plot(t, P, lw=1.2, label="P(t), N = %g%s%s" % (summary["particles"], " lines" if split else "", what))
        if err is not None:  # one standard error either side, where it stays below P
            lo = [max(p - e, p * 1e-3) for p, e in zip(P, err)]
            ax.fill_between(t, lo, [p + e for p, e in zip(P, err)], alpha=0.25, lw=0, color="C0")
        if kappa["value"] is not None:
            # the fit and alpha's factor x the fit over the whole range (down to the smallest P drawn)
            k, lna = kappa["value"], kappa["log_amplitude"]
            floor = min(P) / 10 if P else 0
            factor = alpha.get("factor", 10)
            tt = [x for x in t if math.exp(lna - k * x) * factor >= floor]
            ax.plot(tt, [math.exp(lna - k * x) for x in tt], "--", lw=1, color="C1",
                    label="exp fit: kappa = %.4g +- %.1g on [%g, %g]" % (k, kappa["error"], *kappa["window"]))
            ax.plot(tt, [factor * math.exp(lna - k * x) for x in tt], ":", lw=1, color="C1",
                    label="%g x the fit (alpha's line)" % factor)
        if alpha["value"] is not None:
            ax.plot([alpha["crossing_time"]], [alpha["value"]], "o", color="C3",
                    label="alpha = %.3g (t = %g)" % (alpha["value"], alpha["crossing_time"]))
        ax.set_yscale("log")
        if loglog:
            ax.set_xscale("log")
            ax.set_xlim(left=1)
        ax.set_xlabel("t")
        ax.set_ylabel("P(t)")
        ax.grid(True, which="both", alpha=0.3)
    ax1.set_title("log-log")
    ax2.set_title("semi-log")
    # t P(t): flat where P ~ C / t; the amplitude C and its error over the stretch it was measured on
    ax3.plot(t, [x * p for x, p in zip(t, P)], lw=1.2, color="C0", label="t P(t)")
    if err is not None:
        ax3.fill_between(t, [x * max(p - e, p * 1e-3) for x, p, e in zip(t, P, err)],
                         [x * (p + e) for x, p, e in zip(t, P, err)], alpha=0.25, lw=0, color="C0")
    amp: dict[str, Any] = summary["tail"].get("amplitude") or {}
    if amp.get("value") is not None:
        c, e = amp["value"], math.hypot(amp["error"], amp["systematic"])
        ax3.plot([amp["from"], amp["to"]], [c, c], color="C3", lw=1.5,
                 label="C = %.3g +- %.2g +- %.2g on [%g, %g]" % (c, amp["error"], amp["systematic"], amp["from"],
                                                                 amp["to"]))
        ax3.fill_between([amp["from"], amp["to"]], [c - e] * 2, [c + e] * 2, color="C3", alpha=0.2, lw=0)
    else:
        ax3.set_title("t P(t): no amplitude\n" + textwrap.fill(amp.get("note", "not measured"), 70), fontsize=7)
    # the covering model's C (docs/model.md "Predicting the tail from omega") from where it crosses the chaotic
    # part, with its stated error, and its end off a rational
    model = (summary.get("predicted") or {}).get("tail")
    if model and model.get("forms") and model.get("crossing"):
        c, e = model["amplitude"], model["amplitude_error"]
        curve = model.get("curve") or [[model["crossing"], c], [t[-1], c]]  # off a rational: its sweep
        ct, cy = [x for x, _ in curve if x <= t[-1]], [y for x, y in curve if x <= t[-1]]
        ax3.plot(ct, cy, color="C2", lw=1.2, ls="--",
                 label="model: C = %.3g +- %.2g (2 r omega = %s)" % (c, e, model["rational"]))
        ax3.fill_between(ct, [y * (1 - e / c) for y in cy], [y * (1 + e / c) for y in cy], color="C2", alpha=0.12,
                         lw=0)
        if model.get("end") is not None and model["end"] < t[-1]:
            ax3.axvline(model["end"], color="C2", lw=0.8, ls=":", label="model: tail gone by t ~ %.3g" % model["end"])
    ax3.set_xscale("log")
    ax3.set_yscale("log")
    tp = [x * p for x, p in zip(t, P) if x >= 10 and p > 0]
    if tp:  # four decades below the highest t P: a tail's plateau, not the collapse after it
        ax3.set_ylim(bottom=max(tp) * 1e-4, top=max(tp) * 3)
    ax3.set_xlim(left=1)
    ax3.set_xlabel("t")
    ax3.set_ylabel("t P(t)")
    ax3.grid(True, which="both", alpha=0.3)
    ax3.legend(fontsize=8)
    if amp.get("value") is not None:
        ax3.set_title("t P(t): the tail amplitude")
    ax2.legend(fontsize=8)
    leak = summary["scene"]["leak"]
    fig.suptitle("survival: s_L = %s, width = %s, omega = %s (%s tier)" %
                 (leak["start"], leak["width"], leak["omega"], summary["tier"]))
    fig.tight_layout()
    path = os.path.join(out, "survival.png")
    save(fig, path)
    return path


def density(run: Run, out: str) -> Optional[str]:
    """Draws OUT/fc.png from the run's fc.csv (one curve per time window); None when the run has no f_c."""
    fc = run.fc
    if fc is None:
        return None
    summary = run.summary
    s = fc["s"].astype(float).tolist()
    fig, ax = plt.subplots(figsize=(10, 4))
    for column in (c for c in fc.columns if c.startswith("fc")):  # fc[from,to]; count[from,to] beside each
        ax.plot(s, fc[column].astype(float).tolist(), lw=1, label=column.replace("fc", "t in "))
    leak = summary["scene"]["leak"]
    start, width = exact_text(leak["start"]), exact_text(leak["width"])
    if leak["omega"] == "0" and start is not None and width is not None:
        for shift in (-1, 0, 1):  # the leak on the circle s mod 1
            ax.axvspan(start - width / 2 + shift, start + width / 2 + shift, color="C3", alpha=0.25)
        ax.set_xlim(0, 1)
        ax.plot([], [], color="C3", alpha=0.4, lw=6, label="leak")
    ax.set_xlabel("s")
    ax.set_ylabel("f_c(s)")
    ax.set_title("collision density f_c(s): s_L = %s, width = %s, omega = %s, N = %d"
                 % (leak["start"], leak["width"], leak["omega"], summary["particles"]), fontsize=10)
    # the legend beside the axes, where it covers no spike (it once hid one)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    path = os.path.join(out, "fc.png")
    save(fig, path)
    return path


def draw(run: Union[Run, PathLike], out: Optional[PathLike] = None) -> list[str]:
    """Draw a run's survival.png and, where it has f_c, fc.png.

    Parameters
    ----------
    run : Run or a run directory
        A directory is read first (a damaged one is refused with the reason ``rotleak fit`` gives,
        RotleakError).
    out : directory, optional
        Where the pictures go; by default the run's own directory (required for a run made in process).

    Returns
    -------
    list of str
        The paths drawn.
    """
    if not isinstance(run, Run):
        run = read_run(run)
    where = out if out is not None else run.path
    if where is None:
        raise ValueError("out = None: a run made in process has no directory; give out=DIR for its pictures")
    target = os.fspath(where)
    drew = [survival(run, target), density(run, target)]
    return [d for d in drew if d is not None]
