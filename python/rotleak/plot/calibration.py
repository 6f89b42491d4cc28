"""Draw a calibration directory (rotleak calibrate): the seeds' spread of P over the errors the runs
report, and the share of seeds within 2 errors, against t; the honest band shaded."""
from __future__ import annotations

import os
from typing import Union

from ..readers import Calibration, PathLike, read_calibration
from . import plt, save


def draw(calibration: Union[Calibration, PathLike]) -> list[str]:
    """Draw a calibration's calibration.png beside its files.

    Parameters
    ----------
    calibration : Calibration or a calibration directory
        ``rotleak calibrate --out DIR`` (a damaged one is refused: RotleakError).

    Returns
    -------
    list of str
        The path drawn.
    """
    if not isinstance(calibration, Calibration):
        calibration = read_calibration(calibration)
    doc, directory = calibration.document, calibration.path
    table = calibration.table
    band, floor = doc["P"]["band"], doc["P"]["coverage2_floor"]
    ok = table[(table["resolved"] == 1) & (table["sd_over_err"] > 0)]
    t = ok["t"].astype(float).tolist()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6), sharex=True)
    top.axhspan(band[0], band[1], color="C2", alpha=0.15, label="honest: sd / err in [%g, %g]" % tuple(band))
    top.semilogy(t, ok["sd_over_err"].astype(float).tolist(), color="C0", lw=1, label="sd of P / median P_err")
    top.axhline(1, color="k", lw=0.5)
    top.set_ylabel("sd / err")
    top.legend(loc="upper left", fontsize=8)
    top.set_title("%d seeds of %s particles: are the error bars honest? (resolved times only)"
                  % (len(doc["seeds"]), format(doc["particles"], ",")), fontsize=10)
    bottom.axhspan(floor, 1, color="C2", alpha=0.15, label="at least %g%%" % (100 * floor))
    bottom.plot(t, ok["coverage2"].astype(float).tolist(), color="C1", lw=1, label="seeds within 2 errors")
    bottom.plot(t, ok["coverage1"].astype(float).tolist(), color="C3", lw=0.8, alpha=0.7, label="within 1 error")
    bottom.set_ylim(0, 1.02)
    bottom.set_xlabel("t")
    bottom.set_ylabel("coverage")
    bottom.legend(loc="lower left", fontsize=8)
    for ax in (top, bottom):
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(directory, "calibration.png")
    save(fig, path)
    return [path]
