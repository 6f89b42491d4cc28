"""rotleak's pictures: ``/usr/bin/python3 -m rotleak.plot DIR [--format png,pdf]`` (``rotleak plot DIR`` runs it) draws
whatever a rotleak directory holds, beside its files, and prints each picture's caption:

- a run (``rotleak simulate``): survival (P(t) log-log and semi-log with the error band, the kappa fit and the alpha
  crossing, t P(t) with C; a split run's range past ``unresolved_from`` greyed) and fc (the collision density per
  time window, the arcs shaded);
- a scan: scan_survival, scan_<key> (kappa and alpha against each swept key, regimes as a strip),
  scan_alpha_covering;
- a shadow: shadow; a covering: f_L; a regimes search: its coarse scan and regimes; a calibration: calibration; a
  certified sample: certify.

One style for all (STYLE): a journal's column (ONE_COLUMN, 3.4 in) or page (TWO_COLUMN, 7 in) wide, 8 pt text at that
size, one colour per meaning, the details in the caption. ``figures(x)`` gives the pictures as matplotlib Figures
(Drawing: name, figure, caption) of a directory or of the object the package's readers give (a
:class:`~rotleak.Run`, one made in process too, :class:`~rotleak.Scan`, :class:`~rotleak.Calibration`,
:class:`~rotleak.Certification`); ``draw(x, formats="png,pdf")`` saves them. The tables are read by the package's
readers, by column name. Needs matplotlib (Debian: python3-matplotlib)."""
from __future__ import annotations

import csv
import functools
import math
import os
import sys
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any, NamedTuple, Optional, Union

from .. import _require

_require(("matplotlib",), "rotleak.plot")
import matplotlib  # noqa: E402

if "matplotlib.pyplot" not in sys.modules and not os.environ.get("MPLBACKEND"):
    # files, not windows, unless the caller (a notebook) chose a backend already
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..readers import Calibration, Certification, PathLike, RotleakError, Run, Scan, json_document  # noqa: E402

Drawable = Union[Run, Scan, Calibration, Certification, PathLike]

#: Figure widths in inches: a journal's single column (86 mm) and its full page width (178 mm). Every picture is
#: drawn at one of them, so that its fonts (STYLE) are their stated size when printed at that width.
ONE_COLUMN, TWO_COLUMN = 3.4, 7.0
#: The formats ``draw`` writes (``--format``): PNG at 300 dpi, and the vector formats a journal takes.
FORMATS = ("png", "pdf", "svg")
#: One style for every picture: 8 pt text (9 pt titles) at print size, thin lines, fonts kept as text in PDF/SVG.
STYLE = {
    "font.size": 8, "axes.titlesize": 9, "axes.labelsize": 8, "xtick.labelsize": 8, "ytick.labelsize": 8,
    "legend.fontsize": 8, "figure.titlesize": 9, "legend.title_fontsize": 8, "lines.linewidth": 1.0,
    "lines.markersize": 3.5, "axes.linewidth": 0.6, "grid.linewidth": 0.4, "grid.alpha": 0.3,
    "xtick.major.width": 0.6, "ytick.major.width": 0.6, "legend.frameon": False, "legend.handlelength": 1.6,
    "figure.dpi": 100, "savefig.dpi": 300, "pdf.fonttype": 42, "svg.fonttype": "none",
}
#: Colours that mean one thing in every picture: a measurement, its fit, the model, a bound, the leak, and what is
#: not resolved (masked).
MEASURED, FIT, MODEL, BOUND, LEAK, MASKED = "C0", "C1", "C2", "k", "C3", "0.85"


class Drawing(NamedTuple):
    """One picture: its file name without the suffix, the matplotlib Figure, and its caption (what the short title
    leaves out: the scene, the sample, the fits; ``rotleak plot`` prints it beside the file)."""
    name: str
    figure: Any
    caption: str


def styled(make: Callable[..., Any]) -> Callable[..., Any]:
    """Runs a function that builds figures under STYLE (fonts and lines are fixed when an artist is made)."""
    @functools.wraps(make)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with plt.rc_context(STYLE):
            return make(*args, **kwargs)
    return wrapper


def legend_below(fig: Any, axes: Sequence[Any]) -> None:
    """One legend for every panel (each label once), below them in as many columns as fit the figure's width, in
    space kept for it, and the panels laid out above it."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    if not handles:
        fig.tight_layout(pad=0.3)
        return
    renderer = fig.canvas.get_renderer()
    for ncol in range(len(handles), 0, -1):  # the most columns whose legend fits the figure's width
        legend = fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=ncol, bbox_to_anchor=(0.5, 0),
                            borderaxespad=0.2, columnspacing=1.2)
        box = legend.get_window_extent(renderer)
        if box.width <= 0.98 * fig.bbox.width or ncol == 1:
            break
        legend.remove()
    fig.tight_layout(pad=0.3, rect=(0, (box.height + 4) / fig.bbox.height, 1, 1))


def plain_log_labels(ax: Any) -> None:
    """A log y axis that spans less than a decade or two labelled 0.6, not 6 x 10^-1 (minor labels dropped)."""
    from matplotlib import ticker
    ax.yaxis.set_major_formatter(ticker.ScalarFormatter())
    ax.yaxis.set_minor_formatter(ticker.NullFormatter())


def decades(ax: Any, ys: Sequence[float]) -> None:
    """A log axis over whole decades around ys, at least two, so that it has ticks to read (one had one)."""
    ys = [y for y in ys if y > 0]
    if not ys:
        return
    lo, hi = 10 ** math.floor(math.log10(min(ys))), 10 ** math.ceil(math.log10(max(ys)))
    if hi / lo < 100:  # one decade or none: a decade more below, and above too when there was none
        hi = hi * 10 if hi == lo else hi
        lo = lo / 10
    ax.set_ylim(lo, hi)


def mask_unresolved(ax: Any, start: Optional[float], end: float, label: str = "not resolved") -> None:
    """Greys the range t >= start of an axis (P there is a bound, not a measurement); nothing when start is None."""
    if start is not None and start < end:
        ax.axvspan(start, end, color=MASKED, lw=0, zorder=0, label=label)


def save(fig: Any, path: str, close: bool = True) -> None:
    """Writes a figure whole or not at all (a temporary name, then renamed), in the format its suffix names; closes
    it unless another format of it follows (close=False)."""
    stem, _, fmt = path.rpartition(".")
    tmp = "%s.tmp-%d.%s" % (stem, os.getpid(), fmt)
    done = False
    try:
        with plt.rc_context(STYLE):
            fig.savefig(tmp, format=fmt, metadata=_metadata(fmt))
        os.replace(tmp, path)
        done = True
    finally:
        if not done and os.path.exists(tmp):
            os.remove(tmp)  # a full disk leaves no half picture behind
        if close or not done:
            plt.close(fig)


def _metadata(fmt: str) -> Optional[dict[str, Any]]:
    """No creation date in PDF/SVG (the same run draws the same bytes again); PNG has none to drop."""
    if fmt == "pdf":
        return {"CreationDate": None, "Creator": "rotleak"}
    if fmt == "svg":
        return {"Date": None, "Creator": "rotleak"}
    return None


def formats_of(text: Union[str, Sequence[str]]) -> tuple[str, ...]:
    """``"png,pdf"`` or a list of formats, each one of FORMATS; ValueError naming the one not allowed."""
    items = [f.strip().lower() for f in (text.split(",") if isinstance(text, str) else text)]
    for f in items:
        if f not in FORMATS:
            raise ValueError("--format = %s: must be a comma list of %s" % (f, ", ".join(FORMATS)))
    if not items:
        raise ValueError("--format is empty: must be a comma list of %s" % ", ".join(FORMATS))
    return tuple(dict.fromkeys(items))


def write(drawings: Sequence[Drawing], directory: PathLike, formats: Sequence[str] = ("png",)) -> list[str]:
    """Saves each drawing in each format into directory (NAME.png, NAME.pdf, ...); returns the paths, in order."""
    paths = []
    for d in drawings:
        for fmt in formats:
            path = os.path.join(os.fspath(directory), "%s.%s" % (d.name, fmt))
            save(d.figure, path, close=fmt == formats[-1])
            paths.append(path)
    return paths


def label_points(ax: Any, items: Sequence[tuple[float, float, str]]) -> None:
    """Labels each point (x, y, text) beside it, once the axes' limits are set: from the highest point down, a label
    that would overlap an earlier one steps down a line, and one that would leave the axes on the right goes to the
    left of its point. Font size is STYLE's."""
    fig = ax.figure
    per_point = 72.0 / fig.dpi  # display pixels to points
    size = float(plt.rcParams["font.size"])
    right = ax.get_window_extent().x1 * per_point
    boxes: list[tuple[float, float, float, float]] = []  # placed labels, in points: x0, y0, x1, y1
    placed = sorted(((ax.transData.transform((x, y)) * per_point, x, y, text) for x, y, text in items),
                    key=lambda q: -q[0][1])
    for (px, py), x, y, text in placed:
        width = 0.6 * size * len(text)
        left = px + 4 + width > right
        x0 = px - 4 - width if left else px + 4
        y0 = py - size / 2
        while any(x0 < b[2] and b[0] < x0 + width and y0 < b[3] and b[1] < y0 + size for b in boxes):
            y0 -= size + 1
        boxes.append((x0, y0, x0 + width, y0 + size))
        ax.annotate(text, (x, y), textcoords="offset points", xytext=(x0 - px + (width if left else 0), y0 - py),
                    ha="right" if left else "left", va="bottom")


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


def _drawer(what: Drawable) -> tuple[Callable[[Any], list[Drawing]], Any, str]:
    """(the figures function of what's kind, what to hand it, the directory its pictures go to)."""
    from . import calibration, certify, covering, regimes, run, scan, shadow

    if isinstance(what, (Run, Scan, Calibration, Certification)):
        module = {Run: run, Scan: scan, Calibration: calibration, Certification: certify}[type(what)]
        return module.figures, what, os.fspath(what.path) if what.path is not None else ""
    kinds: dict[str, Any] = {"run": run, "scan": scan, "shadow": shadow, "covering": covering, "regimes": regimes,
                             "calibration": calibration, "certification": certify}
    kind = kind_of(what)
    if kind is None:
        raise RotleakError("%s is not a complete rotleak directory (no summary.json of a run, shadow or covering, "
                           "no scan.json, no regimes.json, no calibration.json)" % os.fspath(what))
    return kinds[kind].figures, what, os.fspath(what)


def figures(what: Drawable) -> list[Drawing]:
    """The pictures of what rotleak wrote, as matplotlib Figures (nothing saved).

    Parameters
    ----------
    what : Run, Scan, Calibration, Certification, or a directory
        A run (one made in process too), scan, calibration or certified sample, or any directory a rotleak command
        wrote: a run, scan, calibration, shadow, covering, regimes search or certified sample.

    Returns
    -------
    list of Drawing
        ``(name, figure, caption)`` for each picture: ``survival`` and ``fc`` of a run; ``scan_survival``,
        ``scan_<key>`` and ``scan_alpha_covering`` of a scan; and so on (docs/output.md).
    """
    make, arg, _ = _drawer(what)
    return make(arg)


def draw(what: Drawable, formats: Union[str, Sequence[str]] = ("png",), out: Optional[PathLike] = None) -> list[str]:
    """Draw what rotleak wrote and save the pictures beside its files (or in ``out``).

    Parameters
    ----------
    what : Run, Scan, Calibration, Certification, or a directory
        As for :func:`figures`.
    formats : str or list of str, default ("png",)
        Any of png (300 dpi), pdf, svg: ``"png,pdf"`` or ``["pdf"]``.
    out : directory, optional
        Where the pictures go; by default what's own directory (required for a run made in process).

    Returns
    -------
    list of str
        The paths written, each picture in each format.
    """
    fmts = formats_of(formats)
    make, arg, directory = _drawer(what)
    target = os.fspath(out) if out is not None else directory
    if not target:
        raise ValueError("out = None: a run made in process has no directory; give out=DIR for its pictures")
    return write(make(arg), target, fmts)


def main(argv: Optional[list[str]] = None) -> None:
    """``/usr/bin/python3 -m rotleak.plot DIR [--format png,pdf]``: one line per picture, its path and caption; a
    failure is one line on stderr (exit 2 for a damaged directory or a bad --format, 1 otherwise)."""
    argv = sys.argv[1:] if argv is None else argv
    usage = ("usage: /usr/bin/python3 -m rotleak.plot DIR [--format png,pdf,svg]   (a directory rotleak wrote: run, "
             "scan, shadow, covering, regimes, calibration, certified sample)")
    fmt = "png"
    if len(argv) == 3 and argv[1] == "--format":
        fmt = argv[2]
    elif len(argv) != 1:
        sys.exit(usage)
    try:
        fmts = formats_of(fmt)
        make, arg, directory = _drawer(argv[0])
        drawings = make(arg)
        paths = write(drawings, directory, fmts)
    except (RotleakError, ValueError) as e:  # a damaged directory or a bad format is bad input: exit 2
        print("rotleak.plot: cannot draw %s" % e if isinstance(e, RotleakError) else "rotleak.plot: %s" % e,
              file=sys.stderr)
        sys.exit(2)
    except Exception as e:  # noqa: BLE001 -- every failure of a plot is reported the same way
        sys.exit("rotleak.plot: cannot draw %s: %s: %s" % (argv[0], type(e).__name__, e))
    for k, d in enumerate(drawings):
        print("drew %s: %s" % (", ".join(paths[k * len(fmts):(k + 1) * len(fmts)]), d.caption))
