"""Readers for what rotleak writes (the schemas are in docs/output.md).

``read_run(dir)`` gives a :class:`Run`: ``summary`` (summary.json as a dict), ``scene`` (scene.toml as
a dict), and the tables as pandas DataFrames: ``survival`` (t, survivors, P, P_err), ``fc`` (s, then per
window ``fc[from,to]`` and ``count[from,to]``) and ``escapes`` (id, fate, t, s, collisions), each None
when the run did not record it. ``read_scan(dir)`` gives a :class:`Scan`: ``table`` (table.csv as a
DataFrame, the swept keys and the text columns kept as strings), ``document`` (scan.json) and ``points``
(each point's Run, read when first asked for). ``read_calibration(dir)`` gives a :class:`Calibration`:
``table`` (calibration.csv as a DataFrame), ``document`` (calibration.json), ``statistics`` and ``scan``
(the seeds' runs as a Scan). ``rotleak.simulate`` returns the same Run without the disk.

Both refuse, with one line that says why, a directory that is not a complete run or scan of this
schema. pandas is imported only when a table is asked for. A run's fits are small dataclasses
(:class:`Kappa`, :class:`Alpha`, :class:`Amplitude`); ``summary`` keeps every field as written."""
from __future__ import annotations

import io
import json
import math
import os
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional, Union

if TYPE_CHECKING:
    import pandas

SCHEMA = 1  # summary.json's and scan.json's "schema" this reader understands
#: A file or directory: a str or an os.PathLike.
PathLike = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class Kappa:
    """The exponential escape rate: a least-squares fit of ln P(t) over ``window`` (docs/model.md).

    Attributes
    ----------
    value : float or None
        kappa; None when the window holds too few resolved points.
    error : float or None
        Its statistical error (one standard deviation).
    systematic : float or None
        The window systematic: half the spread over six windows around the chosen one.
    window : tuple of float
        The fit window ``(from, to)``.
    """

    value: Optional[float]
    error: Optional[float]
    systematic: Optional[float]
    window: tuple[float, float]

    @property
    def total_error(self) -> Optional[float]:
        """The statistical error and the systematic in quadrature (None without an error)."""
        return None if self.error is None else math.hypot(self.error, self.systematic or 0.0)

    @classmethod
    def from_summary(cls, doc: dict[str, Any]) -> Kappa:
        """From summary.json's ``kappa`` object."""
        window = doc.get("window") or [math.nan, math.nan]
        return cls(doc.get("value"), doc.get("error"), doc.get("window_systematic"),
                   (float(window[0]), float(window[1])))


@dataclass(frozen=True)
class Alpha:
    """The algebraic tail's weight: P where it first exceeds ``factor`` times the exponential fit.

    Attributes
    ----------
    value : float or None
        alpha; None where no tail is resolved (then see ``upper_bound``).
    error : float or None
        Its statistical error.
    systematic : float or None
        The window systematic.
    upper_bound : float or None
        Where ``value`` is None: the bound alpha lies below (None when there is none either).
    crossing_time : float or None
        The time of the crossing.
    note : str
        How it was read, or why not.
    """

    value: Optional[float]
    error: Optional[float]
    systematic: Optional[float]
    upper_bound: Optional[float]
    crossing_time: Optional[float]
    note: str

    @classmethod
    def from_summary(cls, doc: dict[str, Any]) -> Alpha:
        """From summary.json's ``alpha`` object."""
        return cls(doc.get("value"), doc.get("error"), doc.get("systematic"), doc.get("upper_bound"),
                   doc.get("crossing_time"), doc.get("note") or "")


@dataclass(frozen=True)
class Amplitude:
    """The tail amplitude C in P ~ C / t: the mean of t P(t) over the stretch where it is flat.

    Attributes
    ----------
    value : float or None
        C; None (with the reason in ``note``) where the tail is not ~1/t or not resolved.
    error : float or None
        Its statistical error (None without a value).
    systematic : float or None
        The drift of t P over the stretch (None without a value).
    stretch : tuple of float, or None
        ``(from, to)`` of the stretch; None where there is none.
    note : str
        Why there is no value, or how it was measured.
    """

    value: Optional[float]
    error: Optional[float]
    systematic: Optional[float]
    stretch: Optional[tuple[float, float]]
    note: str

    @classmethod
    def from_summary(cls, doc: dict[str, Any]) -> Amplitude:
        """From summary.json's ``tail.amplitude`` object."""
        stretch = (float(doc["from"]), float(doc["to"])) if doc.get("from") is not None else None
        return cls(doc.get("value"), doc.get("error"), doc.get("systematic"), stretch, doc.get("note") or "")


class RotleakError(ValueError):
    """A directory or document that is not a complete rotleak output of the schema this reader reads."""


def _pandas() -> Any:
    """pandas, imported when a table is first read (``import rotleak`` has checked it can be imported)."""
    import pandas
    return pandas


def _read_table(source: Union[str, io.StringIO], name: str, where: str, **kw: Any) -> pandas.DataFrame:
    """A CSV table rotleak wrote, read by pandas; a RotleakError naming where and name when pandas cannot."""
    pd = _pandas()
    try:
        # round_trip: each number as the double rotleak wrote (pandas' default parser can miss by an ulp:
        # 0.41421356237309503 once read as 0.414213562373095)
        table: pandas.DataFrame = pd.read_csv(source, float_precision="round_trip", **kw)
    except (ValueError, pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        raise RotleakError("%s: %s: not a table rotleak wrote (%s)" % (where, name, str(e).splitlines()[0])) from None
    return table


def _check_schema(doc: dict[str, Any], what: str, where: str) -> None:
    schema = doc.get("schema")
    if schema is None:
        raise RotleakError("%s: %s has no \"schema\" key: written by a rotleak older than this reader "
                           "(rerun it, or read its files with csv/json)" % (where, what))
    if schema != SCHEMA:
        raise RotleakError("%s: %s has schema %r; this rotleak package reads schema %d" % (where, what, schema, SCHEMA))


def json_document(text: str, name: str, where: str) -> Any:
    """The JSON document `name` of the directory `where`, or a RotleakError with the reason rotleak fit gives
    (analysis/output/run_output.cpp, parse_document)."""
    try:
        return json.loads(text)
    except ValueError:
        raise RotleakError("%s: %s: not valid JSON (damaged or truncated)" % (where, name)) from None


#: A run directory's binary files, kept as bytes: a split run's or a shard's exact tallies (docs/output.md).
BINARY = ("tally.bin",)

_FLOAT = re.compile(r"-?[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?|-?inf|nan")
_COUNT = re.compile(r"[0-9]+")


def check_survival_csv(text: str, t_max: Optional[float] = None, survival_dt: Optional[float] = None,
                       sums: bool = False) -> None:
    """Raises RotleakError with the reason ``rotleak fit`` gives (analysis/output/run_csv.cpp, read_survival_csv,
    word for word) when survival.csv is damaged: its header, a row that ends the file (truncated), a row
    that is not t,survivors,P,P_err (decimals as rotleak writes them; with ``sums``, an importance-sampled run's,
    t,survivors,P,P_err,W,W2 with P = W / W at t = 0), or fewer or more rows than the grid t = k * survival_dt up
    to t_max."""
    columns = "t,survivors,P,P_err,W,W2" if sums else "t,survivors,P,P_err"
    header = columns + "\n"
    if not text.startswith(header):
        raise RotleakError("survival.csv: expected the header " + columns)
    if not text.endswith("\n"):
        raise RotleakError("survival.csv: ends inside a row (truncated)")
    rows = text[len(header):-1].split("\n") if len(text) > len(header) else []
    w0 = 0.0
    for line, row in enumerate(rows, start=2):
        f = row.split(",")
        if len(f) != columns.count(",") + 1 or not _COUNT.fullmatch(f[1]) or int(f[1]) >= 2 ** 64 or not all(
                _FLOAT.fullmatch(x) for k, x in enumerate(f) if k != 1):
            raise RotleakError("survival.csv line %d: expected %s" % (line, columns))
        if sums:  # P = W / W(0), the very doubles rotleak divided
            w0 = float(f[4]) if line == 2 else w0
            if not float(f[2]) == (float(f[4]) / w0 if w0 > 0 else 0.0):
                raise RotleakError("survival.csv line %d: P is not W / W at t = 0" % line)
    if t_max is not None and survival_dt is not None:
        grid = math.ceil(t_max / survival_dt) + 1
        if len(rows) != grid:
            raise RotleakError("survival.csv: %d rows where the grid t = k * survival_dt up to t_max has %d "
                               "(truncated or of another scene)" % (len(rows), grid))


class Run:
    """One run: its summary, its scene and its tables (DataFrames built on first use)."""

    def __init__(self, files: Mapping[str, Union[str, bytes]], path: Optional[PathLike] = None) -> None:
        """files: {name: bytes or str} as a run directory holds them (summary.json required)."""
        self._files = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in files.items() if k not in BINARY}
        self._binary = {k: v for k, v in files.items() if k in BINARY and isinstance(v, bytes)}
        self.path: Optional[str] = os.fspath(path) if path is not None else None
        where = self.path or "rotleak.simulate"
        if "summary.json" not in self._files:
            raise RotleakError("%s: not a complete run directory (no summary.json: a run directory appears only "
                               "when complete; an interrupted one leaves DIR.checkpoint for --resume)" % where)
        self.summary = json_document(self._files["summary.json"], "summary.json", where)
        if not isinstance(self.summary, dict) or self.summary.get("command") != "simulate" or not isinstance(
                self.summary.get("scene"), dict):
            raise RotleakError("%s: summary.json: not a simulate run's summary" % where)
        _check_schema(self.summary, "summary.json", where)
        if "survival.csv" in self._files:
            try:
                sc = self.summary["scene"]
                t_max, dt = float(sc["run"]["t_max"]), float(sc["observe"]["survival_dt"])
                # an importance-sampled run that is not split keeps its weight sums (docs/output.md)
                sums = sc["ensemble"].get("sampling", "uniform") != "uniform" and sc["run"].get("splitting") is not True
            except (KeyError, TypeError, ValueError):
                raise RotleakError("%s: summary.json: not a simulate run's summary" % where) from None
            try:
                check_survival_csv(self._files["survival.csv"], t_max, dt, sums)
            except RotleakError as e:
                raise RotleakError("%s: %s" % (where, e)) from None
        missing = [f for f in self.summary.get("files", [])
                   if f not in self._files and f not in self._binary and not f.endswith(".png")]
        if missing:
            raise RotleakError("%s: incomplete run: summary.json lists %s, which %s missing"
                               % (where, ", ".join(missing), "is" if len(missing) == 1 else "are"))
        self._tables: dict[str, pandas.DataFrame] = {}

    @classmethod
    def from_directory(cls, path: PathLike) -> Run:
        """The run directory ``path`` (what :func:`read_run` does)."""
        if not os.path.isdir(path):
            raise RotleakError("%s: no such directory" % path)
        files: dict[str, Union[str, bytes]] = {}
        for name in ("summary.json", "survival.csv", "lines.csv", "fc.csv", "escapes.csv", "leaks.csv",
                     "scene.toml") + tuple(BINARY):
            p = os.path.join(path, name)
            if os.path.exists(p):
                with open(p, "rb") as f:
                    files[name] = f.read()
        return cls(files, path)

    def _table(self, name: str, **kw: Any) -> Optional[pandas.DataFrame]:
        if name not in self._files:
            return None
        if name not in self._tables:
            self._tables[name] = _read_table(io.StringIO(self._files[name]), name, self.path or "rotleak.simulate",
                                             **kw)
        return self._tables[name]

    @property
    def survival(self) -> pandas.DataFrame:
        """t, survivors, P, P_err: P(t) on the grid t = k survival_dt with one standard error (an importance-sampled
        run's also W, W2: the survivors' weight sums over N)."""
        return self._table("survival.csv")

    @property
    def lines(self) -> Optional[pandas.DataFrame]:
        """Split runs: t, P, R (before the allowance), lines_alive, unsplit_lines, unsplit_P, then per weight
        class c lines_c<c>, P_c<c>, var_c<c> (docs/output.md, lines.csv); None for a run without splitting."""
        return self._table("lines.csv")

    @property
    def fc(self) -> Optional[pandas.DataFrame]:
        """s (bin centre), then per time window fc[from,to] (normalised density) and count[from,to]."""
        return self._table("fc.csv")

    @property
    def escapes(self) -> Optional[pandas.DataFrame]:
        """id, fate (escaped, survived, stuck), t, s, collisions, and with several leaks leak (the escape's leak, an
        integer column with <NA> where none took the particle): one row per particle."""
        return self._table("escapes.csv", dtype={"fate": str, "leak": "Int64"})

    @property
    def leaks(self) -> Optional[pandas.DataFrame]:
        """Scenes of several leaks: t_from, t_to, then escaped_<j> -- the escapes through leak j in each survival bin
        [t_from, t_to) (docs/output.md, leaks.csv); None for one leak. summary.json's ``leaks`` gives each leak's
        keys, total and share of the particles."""
        return self._table("leaks.csv")

    @property
    def scene(self) -> dict[str, Any]:
        """The effective scene (scene.toml) as a dict; exact values stay the texts given."""
        text = self._files.get("scene.toml")
        return tomllib.loads(text) if text is not None else self.summary.get("scene")

    @property
    def kappa(self) -> Kappa:
        """The exponential escape rate with its errors (summary.json's ``kappa``)."""
        return Kappa.from_summary(self.summary["kappa"])

    @property
    def alpha(self) -> Alpha:
        """The tail's weight, or its bound (summary.json's ``alpha``)."""
        return Alpha.from_summary(self.summary["alpha"])

    @property
    def tail(self) -> dict[str, Any]:
        """summary.json's ``tail``: ``class`` (none, transient, persistent, unresolved), ``regime``, ..."""
        tail: dict[str, Any] = self.summary["tail"]
        return tail

    @property
    def tail_amplitude(self) -> Amplitude:
        """C in P ~ C / t with its errors (summary.json's ``tail.amplitude``)."""
        return Amplitude.from_summary(self.summary["tail"]["amplitude"])

    def text(self, name: str) -> str:
        """A file of the run exactly as written (or as rotleak simulate would write it)."""
        return self._files[name]

    def write(self, directory: PathLike) -> PathLike:
        """Writes the run's files into a new directory (each whole: a temporary name, then renamed)."""
        os.makedirs(directory, exist_ok=False)
        files: list[tuple[str, bytes]] = [(k, v) for k, v in self._binary.items()]
        files += [(k, v.encode("utf-8")) for k, v in self._files.items()]  # summary.json last, as written
        for name, data in files:
            tmp = os.path.join(directory, "." + name + ".tmp")
            with open(tmp, "wb") as f:
                f.write(data)
            os.replace(tmp, os.path.join(directory, name))
        return directory

    def __repr__(self) -> str:
        k = self.summary["kappa"]
        return "<rotleak.Run %s: %d particles, kappa = %s, tail = %s>" % (
            self.path or "in process", self.summary["particles"], k["value"], self.summary["tail"]["class"])


def read_run(path: PathLike) -> Run:
    """Read a run directory.

    Parameters
    ----------
    path : str or path
        A directory ``rotleak simulate --out`` wrote.

    Returns
    -------
    Run

    Raises
    ------
    RotleakError
        Not a complete run of this schema (the reason in one line).
    """
    return Run.from_directory(path)


def _is_scan_document(doc: Any) -> bool:
    """The rules rotleak fit reads scan.json by (analysis/output/run_output.cpp, read_scan_document): a scan's
    object whose axes hold a key and text values and whose points name a directory with the swept values."""
    if not isinstance(doc, dict) or doc.get("command") != "scan":
        return False
    axes, points = doc.get("axes"), doc.get("points")
    if not isinstance(axes, list) or not isinstance(points, list):
        return False
    for a in axes:
        if not isinstance(a, dict) or not isinstance(a.get("key"), str) or not isinstance(a.get("values"), list):
            return False
        if not all(isinstance(v, str) for v in a["values"]):
            return False
    for p in points:
        if not isinstance(p, dict) or not isinstance(p.get("point"), str) or not isinstance(p.get("values"), dict):
            return False
        if "number_theory" not in p or p["point"] in ("", ".", "..") or "/" in p["point"]:
            return False
        if not all(isinstance(p["values"].get(a["key"]), str) for a in axes):
            return False
    return "fit_overrides" not in doc or isinstance(doc["fit_overrides"], list)


def _command_document(directory: PathLike, name: str, command: str, kind: str) -> Any:
    """The JSON document `name` of the directory `path` that the rotleak command `command` writes (a `kind`
    directory), or a RotleakError: no directory, no document (incomplete), not JSON, another command's."""
    path = os.fspath(directory)
    if not os.path.isdir(path):
        raise RotleakError("%s: no such directory" % path)
    doc_path = os.path.join(path, name)
    if not os.path.exists(doc_path):
        raise RotleakError("%s: not a complete %s directory (no %s)" % (path, kind, name))
    with open(doc_path, encoding="utf-8") as f:
        doc = json_document(f.read(), name, path)
    if isinstance(doc, dict) and doc.get("command") != command:
        raise RotleakError("%s: %s is not a %s's (command = %r)" % (path, name, kind, doc.get("command")))
    return doc


def read_summary_and_table(path: PathLike, table: str) -> tuple[dict[str, Any], pandas.DataFrame]:
    """The summary.json and one CSV table of a directory a rotleak command wrote (a shadow's shadow.csv, a
    covering's f_L.csv), each read with the standard readers; RotleakError if summary.json is not JSON."""
    directory = os.fspath(path)
    with open(os.path.join(directory, "summary.json"), encoding="utf-8") as f:
        summary = json_document(f.read(), "summary.json", directory)
    return summary, _pandas().read_csv(os.path.join(directory, table), float_precision="round_trip")


class Scan:
    """A scan: its table, its scan.json and each point's run."""

    def __init__(self, directory: PathLike) -> None:
        path = os.fspath(directory)
        self.document = _command_document(path, "scan.json", "scan", "scan")
        if not _is_scan_document(self.document):
            raise RotleakError("%s: scan.json: not a scan's document" % path)
        _check_schema(self.document, "scan.json", path)
        if not os.path.exists(os.path.join(path, "table.csv")):
            raise RotleakError("%s: incomplete scan: no table.csv" % path)
        self.path = path
        self._table: Optional[pandas.DataFrame] = None
        self._points: dict[str, Run] = {}

    @property
    def keys(self) -> list[str]:
        """The swept keys, in the order of the table's first columns."""
        return [a["key"] for a in self.document["axes"]]

    @property
    def table(self) -> pandas.DataFrame:
        """table.csv: the swept keys (exact texts, as strings), the fits, the regime, the number theory."""
        if self._table is None:
            text_columns = self.keys + ["tail", "regime", "cf_2r_omega", "best_approximation", "predicted_tail"]
            self._table = _read_table(os.path.join(self.path, "table.csv"), "table.csv", self.path,
                                      dtype={c: str for c in text_columns}, keep_default_na=False,
                                      na_values={c: [""] for c in ["kappa", "kappa_err", "alpha", "alpha_err",
                                                                   "alpha_syst", "alpha_bound", "tail_end",
                                                                   "tail_amplitude", "tail_amplitude_err",
                                                                   "tail_amplitude_syst", "predicted_amplitude",
                                                                   "predicted_tail_end", "tau1", "tau2",
                                                                   "best_error", "omega_value"]})
            if list(self._table.columns[:len(self.keys)]) != self.keys or len(self._table) != len(self.point_names):
                raise RotleakError("%s: table.csv: not the table of scan.json (other columns or rows)" % self.path)
        return self._table

    @property
    def point_names(self) -> list[str]:
        """The points' directory names, in the table's order."""
        return [p["point"] for p in self.document["points"]]

    def point(self, name: str) -> Run:
        """The run of one point (its directory name, as in scan.json's points)."""
        if name not in self._points:
            self._points[name] = read_run(os.path.join(self.path, "points", name))
        return self._points[name]

    @property
    def points(self) -> dict[str, Run]:
        """{point name: Run}, every point read."""
        return {name: self.point(name) for name in self.point_names}

    def __repr__(self) -> str:
        return "<rotleak.Scan %s: %d points over %s>" % (self.path, len(self.point_names), ", ".join(self.keys))


def read_scan(path: PathLike) -> Scan:
    """Read a scan directory.

    Parameters
    ----------
    path : str or path
        A directory ``rotleak scan --out`` wrote.

    Returns
    -------
    Scan
    """
    return Scan(path)


_CALIBRATION_COLUMNS = ["t", "resolved", "seeds", "P", "P_err", "P_err_model", "sd_over_err", "chi2_dof", "coverage1",
                        "coverage2", "max_over_median"]


class Calibration:
    """A calibration (rotleak calibrate): per grid time the seeds' spread of P against the errors the runs
    report (``table``), the same per statistic (``statistics``: kappa, alpha, ..., stat. and ``_total``), P's
    summary over its resolved times (``P``), and the seeds' runs (``scan``)."""

    def __init__(self, directory: PathLike) -> None:
        path = os.fspath(directory)
        self.document = _command_document(path, "calibration.json", "calibrate", "calibration")
        if not isinstance(self.document, dict):
            raise RotleakError("%s: calibration.json is not a calibration's" % path)
        _check_schema(self.document, "calibration.json", path)
        for key, kind in (("seeds", list), ("P", dict), ("statistics", dict), ("alpha_bounds", dict),
                          ("pooled", dict)):
            if not isinstance(self.document.get(key), kind):
                raise RotleakError("%s: calibration.json: %s is not a%s %s" % (path, key, "n" if kind is dict else "",
                                                                             "object" if kind is dict else "array"))
        if not os.path.exists(os.path.join(path, "calibration.csv")):
            raise RotleakError("%s: incomplete calibration: no calibration.csv" % path)
        self.path = path
        self._table: Optional[pandas.DataFrame] = None

    @property
    def table(self) -> pandas.DataFrame:
        """calibration.csv as a DataFrame, one row per grid time."""
        if self._table is None:
            self._table = _read_table(os.path.join(self.path, "calibration.csv"), "calibration.csv", self.path)
            if list(self._table.columns) != _CALIBRATION_COLUMNS:
                raise RotleakError("%s: calibration.csv: columns %s, not %s"
                                   % (self.path, list(self._table.columns), _CALIBRATION_COLUMNS))
        return self._table

    @property
    def statistics(self) -> dict[str, Any]:
        """Per statistic (kappa, alpha, ..., and their ``_total`` rows): the seeds' spread against the errors."""
        return self.document["statistics"]

    @property
    def P(self) -> dict[str, Any]:
        """P(t)'s summary over its resolved grid times (``honest``, ranges of sd/err and coverage)."""
        return self.document["P"]

    @property
    def scan(self) -> Scan:
        """The seeds' runs, a :class:`Scan` over ensemble.seed."""
        return Scan(self.path)

    def __repr__(self) -> str:
        honest = self.document["P"].get("honest")
        return "<rotleak.Calibration %s: %d seeds, P %s>" % (
            self.path, len(self.document["seeds"]), "honest" if honest else "not honest" if honest is False else
            "not resolved anywhere")


def read_calibration(path: PathLike) -> Calibration:
    """Read a calibration directory.

    Parameters
    ----------
    path : str or path
        A directory ``rotleak calibrate --out`` wrote.

    Returns
    -------
    Calibration
    """
    return Calibration(path)


class Certification:
    """A certified sample (``rotleak certify SCENE --sample N --out DIR``): per particle its proven escape
    (``escapes``), the sample's survival curve between proven bounds with the point tiers' curves of the same
    ids (``bracket``), and the summary (``document``: proven_fraction, bits, each tier judged)."""

    def __init__(self, directory: PathLike) -> None:
        path = os.fspath(directory)
        self.document = _command_document(path, "summary.json", "certify", "certified sample")
        if not isinstance(self.document, dict):
            raise RotleakError("%s: summary.json is not a certified sample's" % path)
        _check_schema(self.document, "summary.json", path)
        tiers = self.document.get("tiers")
        if not isinstance(tiers, list) or not all(isinstance(t, dict) and isinstance(t.get("tier"), str) for t in tiers):
            raise RotleakError("%s: summary.json: tiers is not an array of objects with a tier" % path)
        for key in ("sample", "t_cap", "proven_fraction"):
            value = self.document.get(key)
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise RotleakError("%s: summary.json: %s is not a number" % (path, key))
        for name in ("escapes.csv", "bracket.csv"):
            if not os.path.exists(os.path.join(path, name)):
                raise RotleakError("%s: incomplete certified sample: no %s" % (path, name))
        self.path = path
        self._escapes: Optional[pandas.DataFrame] = None
        self._bracket: Optional[pandas.DataFrame] = None

    @property
    def tiers(self) -> list[str]:
        """The point tiers judged against the bracket."""
        return [str(t["tier"]) for t in self.document["tiers"]]

    @property
    def proven_fraction(self) -> float:
        """The share of the sample whose escape (or survival past the cap) is proven."""
        return float(self.document["proven_fraction"])

    @property
    def escapes(self) -> pandas.DataFrame:
        """escapes.csv as a DataFrame, one row per particle id."""
        if self._escapes is None:
            table = _read_table(os.path.join(self.path, "escapes.csv"), "escapes.csv", self.path)
            want = ["id", "status", "t_lo", "t_hi", "collisions", "bits"] + ["t_" + t for t in self.tiers]
            if list(table.columns) != want:
                raise RotleakError("%s: escapes.csv: columns %s, not %s" % (self.path, list(table.columns), want))
            self._escapes = table
        return self._escapes

    @property
    def bracket(self) -> pandas.DataFrame:
        """bracket.csv as a DataFrame: t, lower, upper, and p_<tier> per tier."""
        if self._bracket is None:
            table = _read_table(os.path.join(self.path, "bracket.csv"), "bracket.csv", self.path)
            want = ["t", "lower", "upper"] + ["p_" + t for t in self.tiers]
            if list(table.columns) != want:
                raise RotleakError("%s: bracket.csv: columns %s, not %s" % (self.path, list(table.columns), want))
            self._bracket = table
        return self._bracket

    def __repr__(self) -> str:
        return "<rotleak.Certification %s: %d particles to t = %g, %.4f%% proven>" % (
            self.path, self.document["sample"], self.document["t_cap"], 100 * self.proven_fraction)


def read_certification(path: PathLike) -> Certification:
    """Read a certified sample's directory.

    Parameters
    ----------
    path : str or path
        A directory ``rotleak certify SCENE --sample N --out`` wrote.

    Returns
    -------
    Certification
    """
    return Certification(path)
