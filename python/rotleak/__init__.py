"""rotleak from Python: open chaotic billiards (the Bunimovich stadium with a rotating leak).

Read what the command line wrote::

    run = rotleak.read_run("runs/quick")          # .summary, .scene, .survival, .fc, .escapes, .kappa, .alpha
    scan = rotleak.read_scan("runs/scan")         # .table (DataFrame), .points (each a Run)

Or run in process, the same library as ``rotleak simulate`` without the disk::

    run = rotleak.simulate("quickstart.toml", particles=10**6, overrides={"leak.omega": "2/3"})
    run.kappa.value, run.survival                     # the same object read_run gives

The covering model's tail for a scene, without a run (docs/model.md, "Predicting the tail from omega")::

    rotleak.predict("quickstart.toml", overrides={"leak.omega": "1/3"})["amplitude"]   # C = 0.405

Exact number theory of the leak's speed and its MUPO covering::

    rotleak.omega("70/71")["convergents"]            # exact, as strings; .fractions() as Fractions
    rotleak.covering("2/3", delta="1e-7")             # f_L(s) of a bouncing-ball crossing

Pictures: ``rotleak.plot.draw(run_or_dir)`` (``/usr/bin/python3 -m rotleak.plot DIR``). The schemas of every file
are in docs/output.md; ``rotleak.__version__`` is the version rotleak --version and summary.json report.
"""
from __future__ import annotations

import io
import json
import os
from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Union

try:
    from ._version import __version__  # type: ignore[import]  # written by the build (cmake/version.cmake)
    from ._version import python as _built_for
except ImportError:  # the source tree's python/, not a build or an install
    __version__ = "unknown"
    _built_for = ""


def _missing(modules: Sequence[str]) -> list[str]:
    """The modules of ``modules`` this interpreter cannot import (looked up, not imported)."""
    import importlib.util
    return [m for m in modules if importlib.util.find_spec(m) is None]


def _require(modules: Sequence[str], what: str) -> None:
    """An ImportError naming the modules this interpreter lacks, and the interpreter that has them."""
    missing = _missing(modules)
    if missing:
        import sys
        other = _built_for or "/usr/bin/python3"
        raise ImportError("%s needs %s, which this Python (%s) cannot import. rotleak is built for %s, for which "
                          "scripts/setup.sh installs numpy, pandas and matplotlib (Debian's python3-numpy, "
                          "python3-pandas, python3-matplotlib): run %s, or install %s for this Python"
                          % (what, " and ".join(missing), sys.executable, other, other, " ".join(missing)))


_require(("numpy", "pandas"), "rotleak")
from .readers import (SCHEMA, Alpha, Amplitude, Calibration, Certification, Kappa, PathLike, RotleakError, Run,
                      Scan, read_calibration, read_certification, read_run, read_scan)

if TYPE_CHECKING:
    import pandas

__all__ = ["__version__", "SCHEMA", "RotleakError", "Run", "Scan", "Calibration", "Certification", "Kappa", "Alpha",
           "Amplitude", "read_run", "read_scan", "read_calibration", "read_certification", "Scene", "simulate", "scan",
           "fit", "regimes", "calibrate", "predict", "omega", "covering", "Omega", "Covering", "Value", "Progress",
           "PathLike"]

#: A scene value as Python gives it: exact keys take str, int or Fraction (never float); a list or a dict
#: becomes a TOML array or inline table ({"bins": 10} -> { bins = 10 }).
Value = Union[str, int, float, bool, Fraction, Sequence[Any], Mapping[str, Any]]
#: A scene's sections as keywords: a dict of keys per section (leak={"omega": "2/3"}), or a list of leaks
#: (leaks=[{"width": "0.01"}, ...]).
Sections = Union[Mapping[str, Value], Sequence[Mapping[str, Value]]]
#: progress(done, total, collisions, final): called after blocks of particles.
Progress = Callable[[int, int, int, bool], None]

# the scene's sections (docs/scenes.md): an override's key is "section.key"
_SECTIONS = ("stadium", "table", "leak", "ensemble", "run", "start_splitting", "observe", "fit")
# the keys read exactly (docs/scenes.md): a float would pass its rounding off as the value meant
_EXACT_KEYS = ("stadium.d", "stadium.r", "leak.width", "leak.start", "leak.omega")
# a listed leak's keys (leaks.N.KEY), and those of them read exactly
_LEAK_KEYS = ("loop", "width", "start", "omega")


def _exact_key(key: str) -> bool:
    """Whether a dotted key is read exactly: the stadium's and the leak's, every table parameter, a listed leak's
    width, start and omega."""
    section, _, name = key.partition(".")
    if section == "table":
        return name not in ("kind", "vertices")
    if section == "leaks":
        return name.partition(".")[2] in ("width", "start", "omega")
    return key in _EXACT_KEYS


def _exact_text(value: Value) -> str:
    """An exact value as its text (str, int or Fraction)."""
    if isinstance(value, Fraction):
        return _text(value)
    return str(value)


def _leaks_toml(leaks: object) -> str:
    """A list of leaks (dicts of loop, width, start, omega) as the scene's [[leaks]] (docs/scenes.md)."""
    if not isinstance(leaks, (list, tuple)) or not leaks or not all(isinstance(x, Mapping) for x in leaks):
        raise ValueError("leaks = %r: must be a list of dicts, each with width and optionally loop, start, omega, "
                         "e.g. leaks=[{\"width\": \"0.01\"}, {\"width\": \"0.01\", \"start\": \"1/2\"}]" % (leaks,))
    out = ""
    for i, leak in enumerate(leaks):
        out += "\n[[leaks]]\n"
        for name, v in leak.items():
            key = "leaks.%d.%s" % (i, name)
            if name not in _LEAK_KEYS:
                raise ValueError("%s = %r: unknown key; a leak takes %s" % (key, v, ", ".join(_LEAK_KEYS)))
            if name == "loop":
                if isinstance(v, bool) or not isinstance(v, int):
                    raise ValueError("%s = %r: must be an int (0: the outer boundary, k: scatterer k)" % (key, v))
                out += "loop = %d\n" % v
                continue
            _check_exact(key, v)
            out += "%s = %s\n" % (name, json.dumps(_exact_text(v)))
    return out


def _without_leaks(text: str) -> str:
    """Scene TOML without its [leak] section and [[leaks]] blocks (each runs to the next header)."""
    out, skip = [], False
    for line in text.splitlines(keepends=True):
        head = line.strip()
        if head.startswith("["):
            skip = head in ("[leak]", "[[leaks]]")
        if not skip:
            out.append(line)
    return "".join(out)


def _check_exact(key: str, value: Value) -> None:
    if isinstance(value, (float, bool)) or not isinstance(value, (int, str, Fraction)):
        raise ValueError("overrides[%r] = %r: %s is exact; give a string (\"2/3\", \"ln(19)\"), an int or a Fraction, "
                         "not a %s (its value is a nearby binary fraction)" % (key, value, key, type(value).__name__))


def _module() -> Any:
    try:
        from . import _rotleak  # type: ignore[attr-defined]  # the compiled module, beside the package
    except ImportError as e:
        raise ImportError("rotleak's in-process module (_rotleak) is not built or not installed beside this package "
                          "(build with pybind11: Debian pybind11-dev python3-dev); the readers and plots work without "
                          "it") from e
    return _rotleak


def _text(value: Value) -> str:
    """A Python value as a scene's text: exact for int, str and Fraction; floats by their shortest repr."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Fraction):
        return "%d/%d" % (value.numerator, value.denominator) if value.denominator != 1 else str(value.numerator)
    if isinstance(value, Mapping):  # a TOML inline table: {"bins": 10} -> { bins = 10 }
        return "{ " + ", ".join("%s = %s" % (k, _text(v) if not isinstance(v, str) else json.dumps(v))
                                for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_text(v) if not isinstance(v, str) else json.dumps(v) for v in value) + "]"
    return str(value) if not isinstance(value, float) else repr(value)


def _overrides(name: str, keys: Mapping[str, Value] | None) -> list[str]:
    """The ``section.key=value`` texts of a dict of scene keys (None: none), each checked by _override."""
    if keys is None:
        return []
    if not isinstance(keys, Mapping):
        raise ValueError("%s = %r: must be a dict of scene keys, e.g. {\"leak.omega\": \"2/3\"}" % (name, keys))
    return [_override(k, v) for k, v in keys.items()]


def _override(key: object, value: Value) -> str:
    """One override as the command line's ``section.key=value`` text, its key and exactness checked."""
    section, dot, name = key.partition(".") if isinstance(key, str) else ("", "", "")
    if not dot or (section not in _SECTIONS and section != "leaks") or not name:
        raise ValueError("overrides[%r]: a scene key is \"section.key\" (sections: %s; a listed leak's "
                         "\"leaks.N.key\"), e.g. {\"leak.omega\": \"2/3\"}" % (key, ", ".join(_SECTIONS)))
    if isinstance(key, str) and _exact_key(key):
        _check_exact(key, value)
    if key == "table.vertices" and isinstance(value, (list, tuple)):  # exact coordinates, quoted
        return "%s=[%s]" % (key, ", ".join("[%s]" % ", ".join(json.dumps(_exact_text(c)) for c in xy)
                                            if isinstance(xy, (list, tuple)) else json.dumps(_exact_text(xy))
                                            for xy in value))
    return "%s=%s" % (key, _text(value))


class Scene:
    """A scene built in Python (docs/scenes.md), checked by rotleak's own reader and held as the TOML rotleak writes.

    ``Scene({"leak.omega": "2/3", "ensemble.particles": 10000})`` takes dotted keys;
    ``Scene(leak={"omega": "2/3"}, ensemble={"particles": 10000})`` takes sections as keywords;
    ``Scene(table={"kind": "circle", "radius": 1}, leaks=[{"width": "0.02"}, {"width": "0.02", "start": "1/4"}])``
    any table and a list of leaks (docs/tables.md; a listed leak's key is then ``leaks.N.key``);
    ``Scene.read(path)`` a scene file and ``Scene.from_toml(text)`` its text, each with the same keys on top. Keys
    left out keep their defaults. Exact keys (stadium.d, stadium.r, leak.width, leak.start, leak.omega, the table's
    parameters and vertices, a listed leak's width, start and omega) take str, int or Fraction, never float. A bad key or value raises ValueError with the one line ``rotleak`` prints for it.
    :meth:`to_toml` is the scene exactly (every key, exact values as their text); :meth:`save` writes it, and
    ``rotleak simulate`` of that file runs what :func:`simulate` of this Scene runs, bit for bit.
    """

    def __init__(self, keys: Mapping[str, Value] | None = None, **sections: Sections) -> None:
        self._toml = Scene._checked("", keys, sections)

    @staticmethod
    def _checked(base: str, keys: Mapping[str, Value] | None, sections: dict[str, Any]) -> str:
        texts = _overrides("keys", keys)
        if "leaks" in sections:  # a list of leaks: the scene's [[leaks]], in place of the base's leak or leaks
            base = _without_leaks(base) + _leaks_toml(sections.pop("leaks"))
        for section, table in sections.items():
            if section not in _SECTIONS or not isinstance(table, Mapping):
                raise ValueError("%s = %r: a section is one of %s, given as a dict of its keys, e.g. "
                                 "leak={\"omega\": \"2/3\"}" % (section, table, ", ".join(_SECTIONS)))
            texts += [_override("%s.%s" % (section, name), v) for name, v in table.items()]
        text: str = _module().scene_toml(base, texts)
        return text

    @classmethod
    def from_toml(cls, text: str, keys: Mapping[str, Value] | None = None,
                  **sections: Sections) -> "Scene":
        """A scene from TOML text (a scene file's contents), with keys on top."""
        if not isinstance(text, str):
            raise ValueError("text = %r: must be a scene's TOML text (a str)" % (text,))
        scene = cls.__new__(cls)
        scene._toml = Scene._checked(text, keys, sections)
        return scene

    @classmethod
    def read(cls, path: PathLike, keys: Mapping[str, Value] | None = None,
             **sections: Sections) -> "Scene":
        """A scene file (TOML), with keys on top."""
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (OSError, UnicodeDecodeError) as e:
            raise ValueError("scene = %s: cannot be read as a TOML scene file (%s)" % (os.fspath(path), e)) from None
        return cls.from_toml(text, keys, **sections)

    def replace(self, keys: Mapping[str, Value] | None = None, **sections: Sections) -> "Scene":
        """A copy with these keys changed."""
        return Scene.from_toml(self._toml, keys, **sections)

    def to_toml(self) -> str:
        """The scene as TOML: every key, exact values as their text (what ``rotleak`` writes as scene.toml)."""
        return self._toml

    def save(self, path: PathLike) -> None:
        """Writes the scene's TOML to path (a temporary name, then renamed: never half a file)."""
        path = os.fspath(path)
        tmp = "%s.tmp-%d" % (path, os.getpid())
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(self._toml)
        os.replace(tmp, path)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Scene) and other._toml == self._toml

    def __hash__(self) -> int:
        return hash(self._toml)

    def __repr__(self) -> str:
        return "rotleak.Scene.from_toml(%r)" % self._toml


def _scene_source(scene: PathLike | Scene | Mapping[str, Value]) -> tuple[str, bool]:
    """(a path or a Scene's TOML text, whether it is text) for the module; a dict becomes a Scene."""
    if isinstance(scene, Mapping):
        scene = Scene(scene)
    if isinstance(scene, Scene):
        return scene.to_toml(), True
    if not isinstance(scene, (str, bytes, os.PathLike)):
        raise ValueError("scene = %r: must be a scene file's path, a rotleak.Scene or a dict of scene keys" % (scene,))
    if not os.path.exists(scene):
        raise ValueError("scene = %s: no such file (TOML text is a scene through rotleak.Scene.from_toml(text))"
                         % os.fspath(scene))
    return os.fspath(scene), False


def simulate(scene: PathLike | Scene | Mapping[str, Value], particles: int | str | None = None, *,
             overrides: Mapping[str, Value] | None = None, threads: int = 0,
             progress: Progress | None = None) -> Run:
    """Run a scene in process: the files ``rotleak simulate`` writes, byte for byte, without the disk.

    Parameters
    ----------
    scene : str or path, Scene, or dict
        A scene file (TOML; docs/scenes.md), a :class:`Scene`, or a dict of dotted scene keys (made a Scene).
    particles : int or str, optional
        ``ensemble.particles``: an int, or a text such as ``"1e6"`` that is an exact integer >= 1.
    overrides : mapping of str to value, optional
        Scene keys to change, by their dotted names: ``{"leak.omega": "2/3", "run.t_max": 5000,
        "ensemble.sampling": "mupo"}`` (the command line's ``--set``). Exact keys take str, int or Fraction.
    threads : int, default 0
        OpenMP threads; 0 uses every core.
    progress : callable, optional
        Called as ``progress(done, total, collisions, final)`` after blocks of particles.

    Returns
    -------
    Run
        The run, as :func:`read_run` would read its directory; :meth:`Run.write` writes it.

    Raises
    ------
    ValueError
        Bad input, with one line naming the key, the value and what is allowed.
    KeyboardInterrupt
        Ctrl-C: the run stops between blocks (the GIL is released while it works).
    """
    if progress is not None and not callable(progress):
        raise ValueError("progress = %r: must be None or a function progress(done, total, collisions, final)"
                         % (progress,))
    source, is_text = _scene_source(scene)
    texts = _scene_arguments(particles, threads, overrides)
    files = _module().simulate(source, texts, int(threads), progress, is_text)
    return Run(dict(files))


def calibrate(scene: PathLike | Scene | Mapping[str, Value], seeds: int, out: PathLike,
              particles: int | str | None = None, *, first_seed: int = 1, overrides: Mapping[str, Value] | None = None,
              threads: int = 0, force: bool = False) -> Calibration:
    """Run ``rotleak calibrate`` in process: the scene under ``seeds`` seeds, then the calibration.

    Parameters
    ----------
    scene : str or path, Scene, or dict
        A scene file (TOML), a :class:`Scene`, or a dict of dotted scene keys (each seed's run keeps it as
        scene.toml).
    seeds : int
        Number of seeds (>= 2): ``ensemble.seed = first_seed .. first_seed + seeds - 1``.
    out : str or path
        The calibration's directory; seeds already complete there are skipped.
    particles, overrides, threads
        As for :func:`simulate`.
    first_seed : int, default 1
        The first seed.
    force : bool, default False
        Redo every seed, replacing ``out``.

    Returns
    -------
    Calibration
        calibration.csv and calibration.json read back; "are my error bars honest here?" is
        ``.P["honest"]`` and ``.statistics``.
    """
    source, is_text = _scene_source(scene)
    texts = _scene_arguments(particles, threads, overrides)
    _module().calibrate(source, texts, _count("seeds", seeds, 2), _count("first_seed", first_seed, 1),
                        os.fspath(out), int(threads), bool(force), is_text)
    return read_calibration(out)


def _axis(key: object, values: Value) -> str:
    """One swept key as ``rotleak scan --over``'s KEY=VALUES: a list of exact values, or the text of a set
    ("logspace(1e-4,1e-1,4)", "rationals(qmax=5)")."""
    if isinstance(values, str):
        text = _override(key, values).partition("=")[2]  # the key's name checked as --set checks it
    elif isinstance(values, (list, tuple)) and values:
        text = ",".join(_override(key, v).partition("=")[2] for v in values)  # each checked as a value of key
    else:
        raise ValueError("over[%r] = %r: the values of a swept key are a non-empty list ([\"1/2\", \"2/3\"]) or "
                         "the text of a set (\"logspace(1e-4,1e-1,4)\")" % (key, values))
    return "%s=%s" % (key, text)


def scan(scene: PathLike | Scene | Mapping[str, Value], over: Mapping[str, Value], out: PathLike,
         particles: int | str | None = None, *, overrides: Mapping[str, Value] | None = None, threads: int = 0,
         force: bool = False, note: Callable[[str], None] | None = None) -> Scan:
    """Run ``rotleak scan`` in process: one run directory per point of the product of the swept values.

    Parameters
    ----------
    scene : str or path, Scene, or dict
        A scene file (TOML), a :class:`Scene`, or a dict of dotted scene keys.
    over : mapping of str to values
        Swept keys, in order (the last varies fastest): a list of exact values (``{"leak.omega": ["1/2", "2/3",
        Fraction(3, 5)]}``) or the text of a set as ``--over`` takes it (``"logspace(1e-4,1e-1,4)"``,
        ``"rationals(qmax=5)"``, ``"near(2/3,1e-4)"``).
    out : str or path
        The scan's directory; points already complete there are kept (a point whose inputs changed is run again).
    particles, overrides, threads
        As for :func:`simulate` (``overrides`` apply to every point, before the swept keys).
    force : bool, default False
        Redo every point.
    note : callable, optional
        Called with each status line (points done, the time left).

    Returns
    -------
    Scan
        The scan read back (:func:`read_scan`): ``.table`` and each point's :class:`Run`.
    """
    if not isinstance(over, Mapping) or not over:
        raise ValueError("over = %r: must be a dict of swept keys, e.g. {\"leak.omega\": [\"1/2\", \"2/3\"]}" % (over,))
    if note is not None and not callable(note):
        raise ValueError("note = %r: must be None or a function note(line)" % (note,))
    source, is_text = _scene_source(scene)
    texts = _scene_arguments(particles, threads, overrides)
    _module().scan(source, texts, [_axis(k, v) for k, v in over.items()], os.fspath(out), int(threads), bool(force),
                   is_text, note)
    return read_scan(out)


def regimes(scene: PathLike | Scene | Mapping[str, Value], out: PathLike, particles: int | str | None = None, *,
            coarse: str = "logspace(1e-5,1e-1,9)", steps: int = 4, overrides: Mapping[str, Value] | None = None,
            threads: int = 0, note: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Run ``rotleak regimes`` in process: where the tail's regime changes with omega (a coarse scan, then
    bisection of each boundary; resumable).

    Parameters
    ----------
    scene : str or path, Scene, or dict
        A scene file, a :class:`Scene` or a dict of dotted keys; its leak size is the one studied.
    out : str or path
        The directory of the probes (scan directories) and regimes.json.
    particles, overrides, threads
        As for :func:`simulate`.
    coarse : str, default "logspace(1e-5,1e-1,9)"
        The coarse omega values, as ``--coarse`` takes them.
    steps : int, default 4
        Bisection steps per boundary (0-30).
    note : callable, optional
        Called with each status line.

    Returns
    -------
    dict
        regimes.json (docs/output.md): ``boundaries`` (``low_mid``, ``mid_high``), ``reasons``, ``predicted``.
    """
    if note is not None and not callable(note):
        raise ValueError("note = %r: must be None or a function note(line)" % (note,))
    if not isinstance(coarse, str):
        raise ValueError("coarse = %r: must be the text of omega values (\"logspace(1e-5,1e-1,9)\", \"1e-4,1e-3\")"
                         % (coarse,))
    source, is_text = _scene_source(scene)
    texts = _scene_arguments(particles, threads, overrides)
    doc: dict[str, Any] = json.loads(_module().regimes(source, texts, coarse, _count("steps", steps, 0),
                                                       os.fspath(out), int(threads), is_text, note))
    return doc


def fit(what: Run | Scan | PathLike, keys: Mapping[str, Value] | None = None, *,
        note: Callable[[str], None] | None = None, **fit_keys: Value) -> Run | Scan:
    """Refit a saved run or scan under new fit keys, without simulating (``rotleak fit DIR --set fit.KEY=V``).

    Parameters
    ----------
    what : Run, Scan, or a directory
        A run or scan with a directory (a run made in process: :meth:`Run.write` it first).
    keys : mapping, optional
        Dotted fit keys, ``{"fit.kappa_window": [300, 1500]}``.
    **fit_keys
        The same without the section: ``fit(run, kappa_window=[300, 1500], alpha_factor=10)``.
    note : callable, optional
        Called with each status line.

    Returns
    -------
    Run or Scan
        The refitted directory read back; its previous summary.json is kept as summary.prev.json (each point's, for a
        scan). Pictures drawn of the previous fit are not redrawn: ``rotleak.plot.draw`` them again.
    """
    path = what.path if isinstance(what, (Run, Scan)) else what
    if path is None:
        raise ValueError("what: a run made in process has no directory to refit; write it first (run.write(DIR))")
    texts = _overrides("keys", keys) + [_override("fit." + k, v) for k, v in fit_keys.items()]
    is_scan, _, _ = _module().fit(os.fspath(path), texts, note)
    return read_scan(path) if is_scan else read_run(path)


def predict(scene: PathLike | Scene | Mapping[str, Value], *,
            overrides: Mapping[str, Value] | None = None) -> dict[str, Any]:
    """The covering model's tail for a scene, without running it (milliseconds).

    Parameters
    ----------
    scene : str or path, Scene, or dict
        A scene file (TOML), a :class:`Scene`, or a dict of dotted scene keys.
    overrides : mapping of str to value, optional
        As for :func:`simulate`: ``{"leak.omega": "2/5+1e-5"}``.

    Returns
    -------
    dict
        ``rotleak predict --json``'s document: ``forms``, ``amplitude`` (C in P ~ C / t) with
        ``amplitude_error``, ``end``, ``rational``, ``Q``, ``eps``, ``regime``, ``note``, ``candidates``
        (docs/output.md).
    """
    source, is_text = _scene_source(scene)
    texts = _scene_arguments(None, 0, overrides)
    doc: dict[str, Any] = json.loads(_module().predict(source, texts, is_text))
    return doc


def _scene_arguments(particles: int | str | None, threads: int, overrides: Mapping[str, Value] | None) -> list[str]:
    """The scene's override texts from simulate's and calibrate's arguments, each checked by name."""
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
        raise ValueError("threads = %r: must be an integer >= 0 (0: all cores)" % (threads,))
    texts = _overrides("overrides", overrides)
    if particles is not None:
        texts.append("ensemble.particles=%d" % _particle_count(particles))
    return texts


def _count(name: str, value: object, least: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise ValueError("%s = %r: must be an integer >= %d" % (name, value, least))
    return value


def _particle_count(value: object) -> int:
    """An int, or a text "1e6" / "1000000" that is an exact integer >= 1."""
    n: Fraction | None
    try:
        if isinstance(value, bool):  # True is the int 1: not a count anyone means
            raise ValueError(value)
        n = Fraction(str(value)) if not isinstance(value, int) else Fraction(value)
    except (ValueError, ZeroDivisionError):
        n = None
    if n is None or n.denominator != 1 or n < 1:
        raise ValueError("particles = %r: must be an integer >= 1 (1000000, 10**6 or \"1e6\"; not a bool)"
                         % (value,))
    return int(n)


class Omega(dict[str, Any]):
    """``rotleak omega --json``'s document as a dict.

    ``omega["omega"]["cf"]`` holds the certified partial quotients, ``["convergents"]`` the convergents as
    ``[p, q]`` strings, and so on (docs/output.md).
    """

    def fractions(self, key: str = "convergents") -> list[Fraction]:
        """The approximations under ``key`` as Fractions.

        Parameters
        ----------
        key : str, default "convergents"
            ``"convergents"``, ``"semiconvergents"``, ``"best_approximations"`` or
            ``"best_approximations_second_kind"``.
        """
        items = self["omega"][key]
        if isinstance(items, dict):  # best_approximations: {max_den, list}
            items = items["list"]
        out = []
        for item in items:
            if isinstance(item, dict):
                out.append(Fraction(int(item["p"]), int(item["q"])))
            elif isinstance(item, (list, tuple)):
                out.append(Fraction(int(item[0]), int(item[1])))
            else:
                out.append(Fraction(item))
        return out


def omega(value: str | int | Fraction, terms: int = 20, max_den: int = 1000, eps: str | None = None,
          digits: int = 30, convergents: int = 12) -> Omega:
    """The continued fraction, convergents and best approximations of an exact omega.

    Parameters
    ----------
    value : str, int or Fraction
        An exact value: ``"70/71"``, ``"1e-4"``, ``"ln(19)"``, ``"liouville(10)"``.
    terms : int, default 20
        Certified partial quotients to compute.
    max_den : int, default 1000
        Largest denominator of the best approximations.
    eps : str, optional
        Also find the smallest q with ``|omega - p/q| < eps``.
    digits : int, default 30
        Digits of the value's enclosure.
    convergents : int, default 12
        Convergents to list.

    Returns
    -------
    Omega
        ``rotleak omega --json``'s document.
    """
    doc = _module().omega(_text(value), int(terms), str(max_den), "" if eps is None else _text(eps), int(digits),
                          int(convergents))
    return Omega(json.loads(doc))


class Covering:
    """A MUPO covering, as ``rotleak covering`` computes it.

    Attributes
    ----------
    summary : dict
        rotleak covering's summary.json.
    """

    def __init__(self, summary: dict[str, Any], profile: str, segments: Sequence[str]) -> None:
        self.summary, self._profile, self._segments = summary, profile, list(segments)

    @property
    def f_L(self) -> pandas.DataFrame:
        """s, then f_L of each covering averaged over each bin (f_L.csv)."""
        from .readers import _pandas

        return _pandas().read_csv(io.StringIO(self._profile), float_precision="round_trip")

    def segments(self, k: int = 0) -> pandas.DataFrame:
        """The exact breakpoints of the k-th covering: from, to, f_L."""
        from .readers import _pandas

        return _pandas().read_csv(io.StringIO(self._segments[k]), float_precision="round_trip")

    def __repr__(self) -> str:
        cov = self.summary["covering"]
        cov = cov if isinstance(cov, list) else [cov]
        return "<rotleak.Covering %s>" % ", ".join("%s: zero measure %.3g" % (c["omega"], c["zero_measure"])
                                                    for c in cov)


def covering(omega: Value | Sequence[Value], delta: Value | Sequence[Value] = "1e-7", lam: Value = "0.01",
             d: Value = "2", r: Value = "1", resolution: int = 1000) -> Covering:
    """The MUPO covering f_L(s) of the leak during a bouncing-ball crossing.

    Parameters
    ----------
    omega : exact value or list of them
        The leak's speed(s).
    delta : exact value or list of them, default "1e-7"
        The orbit's ``1 + delta = 1 / sqrt(1 - p^2)``; every omega is covered at every delta.
    lam, d, r : exact values
        Leak width, straight-edge length and radius.
    resolution : int, default 1000
        Bins of the ``f_L`` table.

    Returns
    -------
    Covering
    """
    omegas = list(omega) if isinstance(omega, (list, tuple)) else [omega]
    deltas = list(delta) if isinstance(delta, (list, tuple)) else [delta]
    doc, profile, segments = _module().covering([_text(o) for o in omegas], [_text(x) for x in deltas], _text(lam),
                                                _text(d), _text(r), int(resolution))
    return Covering(json.loads(doc), profile, segments)


def __dir__() -> list[str]:
    """What the package offers (its ``__all__``), not the modules it imports (os, json, typing)."""
    return sorted(__all__)
