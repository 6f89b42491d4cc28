"""Draw a calibration directory (rotleak calibrate): the seeds' spread of P over the errors the runs
report, and the share of seeds within 2 errors, against t; the honest band shaded."""
from __future__ import annotations

import math
from typing import Union

from ..readers import Calibration, PathLike, read_calibration
from . import ONE_COLUMN, Drawing, legend_below, mask_unresolved, plain_log_labels, plt, styled
from . import draw as _draw


def draw(calibration: Union[Calibration, PathLike], formats: object = ("png",)) -> list[str]:
    """Draw a calibration's calibration picture beside its files, in each format; returns the paths."""
    return _draw(calibration if isinstance(calibration, Calibration) else read_calibration(calibration),
                 formats)  # type: ignore[arg-type]


@styled
def figures(calibration: Union[Calibration, PathLike]) -> list[Drawing]:
    """calibration: sd / err of P and the coverage against t (a damaged directory is refused: RotleakError)."""
    if not isinstance(calibration, Calibration):
        calibration = read_calibration(calibration)
    doc = calibration.document
    table = calibration.table
    band, floor = doc["P"]["band"], doc["P"]["coverage2_floor"]
    ok = table[(table["resolved"] == 1) & (table["sd_over_err"] > 0)]
    t = ok["t"].astype(float).tolist()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(ONE_COLUMN, 3.8), sharex=True)
    cut = doc["P"].get("model_from")  # the median seed's unresolved_from: P a bound from there
    # the axes end a little past the last time every seed resolves (a plain run's survivors run out there)
    t_end = min(float(table["t"].iloc[-1]), 1.1 * max(t) if t else math.inf)
    for ax in (top, bottom):
        mask_unresolved(ax, cut, t_end, "P a bound")
    top.axhspan(band[0], band[1], color="C2", alpha=0.15, label="honest")
    top.semilogy(t, ok["sd_over_err"].astype(float).tolist(), color="C0", label="sd / err")
    top.axhline(1, color="k", lw=0.5)
    top.set_ylabel("sd of P / median error")
    plain_log_labels(top)
    top.set_title("are the error bars honest?")
    bottom.axhspan(floor, 1, color="C2", alpha=0.15)
    bottom.plot(t, ok["coverage2"].astype(float).tolist(), color="C1", label="within 2 errors")
    bottom.plot(t, ok["coverage1"].astype(float).tolist(), color="C4", lw=0.8, label="within 1 error")
    bottom.set_ylim(0, 1.02)
    bottom.set_xlim(0, t_end)
    bottom.set_xlabel("t")
    bottom.set_ylabel("share of seeds")
    for ax in (top, bottom):
        ax.grid(True, which="major")
    legend_below(fig, (top, bottom))
    caption = ("%d seeds of %s particles: the seeds' spread of P over the median error the runs report (top; green: "
               "sd / err in [%g, %g]) and the share of seeds within 1 and 2 errors of the pooled P (bottom; green: at "
               "least %g%%), at the times every seed resolves%s." % (
                   len(doc["seeds"]), format(doc["particles"], ","), band[0], band[1], 100 * floor,
                   "; grey: t >= %g, where a seed's P is a bound" % cut if cut is not None else ""))
    return [Drawing("calibration", fig, caption)]
