"""rotleak's pictures: ``/usr/bin/python3 -m rotleak.plot DIR`` (``rotleak plot DIR`` runs it) draws whatever a
rotleak directory holds, beside its files:

- a run (``rotleak simulate``): survival.png (P(t) log-log and semi-log, error band, the kappa fit and
  the alpha crossing) and fc.png (the collision density per time window);
- a scan: scan_survival.png, scan_<key>.png (kappa and alpha against each swept key, regimes as a
  strip), scan_alpha_covering.png;
- a shadow: shadow.png; a covering: f_L.png; a regimes search: its coarse scan and regimes.png.

Each drawing is also a function for scripts and notebooks: ``draw(x)`` takes a directory or the object
the package's readers give (a :class:`~rotleak.Run`, :class:`~rotleak.Scan` or
:class:`~rotleak.Calibration`), and ``rotleak.plot.run.draw(run, out=DIR)`` draws an in-process run. The
tables are read by the package's readers, by column name. Needs matplotlib (Debian: python3-matplotlib)."""
from __future__ import annotations

import csv
import os
import sys
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any, Optional, Union

from .. import _require

_require(("matplotlib",), "rotleak.plot")
import matplotlib  # noqa: E402

if "matplotlib.pyplot" not in sys.modules and not os.environ.get("MPLBACKEND"):
    # files, not windows, unless the caller (a notebook) chose a backend already
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..readers import Calibration, Certification, PathLike, RotleakError, Run, Scan, json_document  # noqa: E402

Drawable = Union[Run, Scan, Calibration, Certification, PathLike]
Point = tuple[float, float]


def save(fig: Any, path: str) -> None:
    """Writes a figure whole or not at all (a temporary name, then renamed)."""
    tmp = path + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=120)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)  # a full disk leaves no half picture behind
        raise
    finally:
        plt.close(fig)


def annotate_clear(ax: Any, placed: list[Point], label: str, xy: Point, near: Callable[[Point, Point], bool],
                   offset: tuple[float, float] = (4, 2), step: float = 9, **kw: Any) -> None:
    """Annotates `xy` with `label`, stepped down `step` points for each earlier label in `placed` that
    `near(earlier_xy, xy)` calls close, so that neighbours' labels do not overlap; records `xy` in `placed`."""
    crowd = sum(1 for q in placed if near(q, xy))
    placed.append(xy)
    ax.annotate(label, xy, textcoords="offset points", xytext=(offset[0], offset[1] - step * crowd), **kw)


def exact_text(text: str) -> Optional[float]:
    """A scene's exact value as a float for drawing only ("1/3", "0.1022"); None for irrationals."""
    try:
        return float(Fraction(text))
    except (ValueError, ZeroDivisionError):
        return None


def bench_main(name: str, draw_rows: Callable[[Sequence[dict[str, str]]], Any]) -> None:
    """``/usr/bin/python3 -m rotleak.plot.NAME CSV OUT.png`` for a benchmark's CSV: draw_rows(rows) makes the
    figure from the CSV's rows (csv.DictReader), which is written whole to OUT.png."""
    if len(sys.argv) != 3:
        sys.exit("usage: /usr/bin/python3 -m rotleak.plot.%s CSV OUT.png" % name)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("rotleak.plot.%s: %s has no rows" % (name, sys.argv[1]))
    save(draw_rows(rows), sys.argv[2])
    print("drew " + sys.argv[2])


def kind_of(directory: PathLike) -> Optional[str]:
    """Which rotleak command wrote a directory: run, scan, calibration, shadow, covering, regimes,
    certification; None
    otherwise."""
    if os.path.exists(os.path.join(directory, "calibration.json")):
        return "calibration"
    if os.path.exists(os.path.join(directory, "regimes.json")):
        return "regimes"
    if os.path.exists(os.path.join(directory, "scan.json")):
        return "scan"
    path = os.path.join(directory, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        doc = json_document(f.read(), "summary.json", os.fspath(directory))
    if not isinstance(doc, dict):
        raise RotleakError("%s: summary.json: not a simulate run's summary" % directory)
    if doc.get("command") == "simulate":
        return "run"
    if "truth" in doc:
        return "shadow"
    if "covering" in doc:
        return "covering"
    if doc.get("command") == "certify":
        return "certification"
    return None


def draw(what: Drawable) -> list[str]:
    """Draw what rotleak wrote, beside its files.

    Parameters
    ----------
    what : Run, Scan, Calibration, Certification, or a directory
        A run, scan, calibration or certified sample (a run made in process needs ``rotleak.plot.run.draw(run,
        out=DIR)``), or any directory a rotleak command wrote: a run, scan, calibration, shadow, covering,
        regimes search or certified sample.

    Returns
    -------
    list of str
        The paths of the pictures drawn.
    """
    from . import calibration, certify, covering, regimes, run, scan, shadow

    if isinstance(what, Run):
        return run.draw(what)
    if isinstance(what, Scan):
        return scan.draw(what)
    if isinstance(what, Calibration):
        return calibration.draw(what)
    if isinstance(what, Certification):
        return certify.draw(what)
    directory = what
    kind = kind_of(directory)
    drawers: dict[str, Callable[[PathLike], list[str]]] = {
        "run": run.draw, "scan": scan.draw, "shadow": shadow.draw, "covering": covering.draw,
        "regimes": regimes.draw, "calibration": calibration.draw, "certification": certify.draw}
    if kind is None:
        raise RotleakError("%s is not a complete rotleak directory (no summary.json of a run, shadow or covering, "
                           "no scan.json, no regimes.json, no calibration.json)" % os.fspath(directory))
    return drawers[kind](directory)


def main(argv: Optional[list[str]] = None) -> None:
    """``/usr/bin/python3 -m rotleak.plot DIR``: a failure is one line on stderr and exit 1, not a traceback."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        sys.exit("usage: /usr/bin/python3 -m rotleak.plot DIR   (a run, scan, shadow, covering or regimes directory)")
    try:
        drew = draw(argv[0])
    except RotleakError as e:  # a damaged directory is bad input: its reason, exit 2 (as rotleak fit)
        print("rotleak.plot: cannot draw %s" % e, file=sys.stderr)
        sys.exit(2)
    except Exception as e:  # noqa: BLE001 -- every failure of a plot is reported the same way
        sys.exit("rotleak.plot: cannot draw %s: %s: %s" % (argv[0], type(e).__name__, e))
    print("drew " + ", ".join(drew))
