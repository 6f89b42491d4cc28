"""Draw a calibration directory (rotleak calibrate): the seeds' spread of P over the errors the runs
report, and the share of seeds within 2 errors, against t; the honest band shaded."""
import csv
import json
import os

from . import plt, save


def draw(directory):
    """DIR/calibration.png from DIR/calibration.csv and calibration.json; returns its path."""
    with open(os.path.join(directory, "calibration.json")) as f:
        doc = json.load(f)
    with open(os.path.join(directory, "calibration.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    band, floor = doc["P"]["band"], doc["P"]["coverage2_floor"]
    ok = [r for r in rows if r["resolved"] == "1" and float(r["sd_over_err"]) > 0]
    t = [float(r["t"]) for r in ok]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6), sharex=True)
    top.axhspan(band[0], band[1], color="C2", alpha=0.15, label="honest: sd / err in [%g, %g]" % tuple(band))
    top.semilogy(t, [float(r["sd_over_err"]) for r in ok], color="C0", lw=1, label="sd of P / median P_err")
    top.axhline(1, color="k", lw=0.5)
    top.set_ylabel("sd / err")
    top.legend(loc="upper left", fontsize=8)
    top.set_title("%d seeds of %s particles: are the error bars honest? (resolved times only)"
                  % (len(doc["seeds"]), format(doc["particles"], ",")), fontsize=10)
    bottom.axhspan(floor, 1, color="C2", alpha=0.15, label="at least %g%%" % (100 * floor))
    bottom.plot(t, [float(r["coverage2"]) for r in ok], color="C1", lw=1, label="seeds within 2 errors")
    bottom.plot(t, [float(r["coverage1"]) for r in ok], color="C3", lw=0.8, alpha=0.7, label="within 1 error")
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
