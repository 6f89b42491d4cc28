"""rotleak from Python: open chaotic billiards (the Bunimovich stadium with a rotating leak).

Read what the command line wrote::

    run = rotleak.read_run("runs/quick")          # .summary, .scene, .survival, .fc, .escapes
    scan = rotleak.read_scan("runs/scan")         # .table (DataFrame), .points (each a Run)

Or run in process, the same library as ``rotleak simulate`` without the disk::

    run = rotleak.simulate("quickstart.toml", particles=10**6, threads=2, leak_omega="2/3")
    run.summary["kappa"], run.survival                # the same object read_run gives

The covering model's tail for a scene, without a run (docs/model.md, "Predicting the tail from omega")::

    rotleak.predict("quickstart.toml", leak_omega="1/3")["amplitude"]   # C = 0.405 in P ~ C / t

Exact number theory of the leak's speed and its MUPO covering::

    rotleak.omega("70/71")["convergents"]            # exact, as strings; .fractions() as Fractions
    rotleak.covering("2/3", delta="1e-7")             # f_L(s) of a bouncing-ball crossing

Pictures: ``rotleak.plot.draw(dir)`` (``python3 -m rotleak.plot DIR``). The schemas of every file are
in docs/output.md; ``rotleak.__version__`` is the version rotleak --version and summary.json report.
"""
import io
import json
import os
from fractions import Fraction

try:
    from ._version import __version__  # written by the build (cmake/version.cmake)
except ImportError:  # the source tree's python/, not a build or an install
    __version__ = "unknown"
from .readers import SCHEMA, Calibration, RotleakError, Run, Scan, read_calibration, read_run, read_scan

__all__ = ["__version__", "SCHEMA", "RotleakError", "Run", "Scan", "Calibration", "read_run", "read_scan",
           "read_calibration", "simulate", "calibrate", "predict", "omega", "covering", "Omega", "Covering"]

# scene sections, for keyword overrides: leak_omega="2/3" is --set leak.omega=2/3
_SECTIONS = ("stadium", "leak", "ensemble", "run", "observe", "fit")


def _module():
    try:
        from . import _rotleak
    except ImportError as e:
        raise ImportError("rotleak's in-process module (_rotleak) is not built or not installed beside this package "
                          "(build with pybind11: Debian pybind11-dev python3-dev); the readers and plots work without "
                          "it") from e
    return _rotleak


def _text(value):
    """A Python value as a scene's text: exact for int, str and Fraction; floats by their shortest repr."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Fraction):
        return "%d/%d" % (value.numerator, value.denominator) if value.denominator != 1 else str(value.numerator)
    if isinstance(value, dict):  # a TOML inline table: {"bins": 10} -> { bins = 10 }
        return "{ " + ", ".join("%s = %s" % (k, _text(v) if not isinstance(v, str) else json.dumps(v))
                                for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_text(v) if not isinstance(v, str) else json.dumps(v) for v in value) + "]"
    return str(value) if not isinstance(value, float) else repr(value)


# the keys read exactly (docs/scenes.md): a float would pass its rounding off as the value meant
_EXACT_KEYS = ("stadium.d", "stadium.r", "leak.width", "leak.start", "leak.omega")


def _override(key, value):
    given = key
    if "." not in key:
        section, _, name = key.partition("_")
        if section not in _SECTIONS or not name:
            raise ValueError("%s = %r: a scene override is section_key=value (sections: %s) or set=['section.key=value']"
                             % (key, value, ", ".join(_SECTIONS)))
        key = section + "." + name
    if key in _EXACT_KEYS and (isinstance(value, (float, bool)) or not isinstance(value, (int, str, Fraction))):
        raise ValueError("%s = %r: %s is exact; give a string (\"2/3\", \"ln(19)\"), an int or a Fraction, not a %s "
                         "(its value is a nearby binary fraction)" % (given, value, key, type(value).__name__))
    return "%s=%s" % (key, _text(value))


def simulate(scene, particles=None, threads=0, progress=None, set=(), **overrides):
    """Runs a scene in process and returns its :class:`Run`: the files ``rotleak simulate`` writes,
    byte for byte, without touching the disk.

    scene: a scene file (TOML). particles: ensemble.particles (an int, or a text such as "1e6").
    threads: OpenMP threads (0: all cores). progress: called as progress(done, total, collisions,
    final) after blocks of particles. set: "section.key=value" texts; keyword overrides section_key=value
    (leak_omega="2/3", run_t_max=5000, ensemble_sampling="mupo"). The GIL is released while it runs;
    Ctrl-C stops it between blocks (KeyboardInterrupt). Bad input raises ValueError naming the key."""
    if progress is not None and not callable(progress):
        raise ValueError("progress = %r: must be None or a function progress(done, total, collisions, final)"
                         % (progress,))
    texts = _scene_arguments(scene, particles, threads, set, overrides)
    files = _module().simulate(os.fspath(scene), texts, int(threads), progress)
    return Run(dict(files))


def calibrate(scene, seeds, out, particles=None, first_seed=1, threads=0, force=False, set=(), **overrides):
    """Runs ``rotleak calibrate`` in process: ``seeds`` runs of the scene (ensemble.seed = first_seed ..
    first_seed + seeds - 1) into the directory ``out`` (seeds already complete there are skipped), then
    calibration.csv and calibration.json; returns the :class:`Calibration` read back. The other arguments
    are those of :func:`simulate` (``set`` texts, keyword overrides section_key=value). "Are my error bars
    honest here?": see ``.P["honest"]`` and ``.statistics``."""
    texts = _scene_arguments(scene, particles, threads, set, overrides)
    _module().calibrate(os.fspath(scene), texts, _count("seeds", seeds, 2), _count("first_seed", first_seed, 1),
                        os.fspath(out), int(threads), bool(force))
    return read_calibration(out)


def predict(scene, set=(), **overrides):
    """The covering model's tail for a scene, without running it (milliseconds): ``rotleak predict --json``'s
    document as a dict -- ``forms``, ``amplitude`` (C in P ~ C / t) with ``amplitude_error``, ``end``,
    ``rational``, ``Q``, ``eps``, ``regime``, ``note``, ``candidates`` (docs/output.md). ``set`` and keyword
    overrides as for :func:`simulate` (leak_omega="2/5+1e-5")."""
    texts = _scene_arguments(scene, None, 0, set, overrides)
    return json.loads(_module().predict(os.fspath(scene), texts))


def _scene_arguments(scene, particles, threads, set, overrides):
    """The scene's override texts from simulate's and calibrate's arguments, each checked by name."""
    if isinstance(set, str):
        set = [set]
    if not isinstance(set, (list, tuple)) or not all(isinstance(x, str) for x in set):
        raise ValueError("set = %r: must be a list of texts 'section.key=value'" % (set,))
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
        raise ValueError("threads = %r: must be an integer >= 0 (0: all cores)" % (threads,))
    texts = list(set) + [_override(k, v) for k, v in overrides.items()]
    if particles is not None:
        texts.append("ensemble.particles=%d" % _particle_count(particles))
    if not os.path.exists(scene):
        raise ValueError("scene = %s: no such file" % scene)
    return texts


def _count(name, value, least):
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise ValueError("%s = %r: must be an integer >= %d" % (name, value, least))
    return value


def _particle_count(value):
    """An int, or a text "1e6" / "1000000" that is an exact integer >= 1."""
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


class Omega(dict):
    """rotleak omega's document (a dict: ``omega["omega"]["cf"]`` the certified partial quotients,
    ``["convergents"]`` as [p, q] strings, ...); ``fractions("convergents")`` (or
    "best_approximations", "best_approximations_second_kind") gives them as Python Fractions."""

    def fractions(self, key="convergents"):
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


def omega(value, terms=20, max_den=1000, eps=None, digits=30, convergents=12):
    """The continued fraction, convergents and best approximations of an exact omega ("70/71", "1e-4",
    "ln(19)", "liouville(10)", a Fraction or an int): ``rotleak omega --json``'s document."""
    doc = _module().omega(_text(value), int(terms), str(max_den), "" if eps is None else _text(eps), int(digits),
                          int(convergents))
    return Omega(json.loads(doc))


class Covering:
    """A MUPO covering: ``summary`` (rotleak covering's summary.json), ``f_L`` (a DataFrame: s, then
    f_L of each covering averaged over each bin) and ``segments(k)`` (the exact breakpoints of the
    k-th covering: from, to, f_L)."""

    def __init__(self, summary, profile, segments):
        self.summary, self._profile, self._segments = summary, profile, segments

    @property
    def f_L(self):
        from .readers import _pandas

        return _pandas().read_csv(io.StringIO(self._profile))

    def segments(self, k=0):
        from .readers import _pandas

        return _pandas().read_csv(io.StringIO(self._segments[k]))

    def __repr__(self):
        cov = self.summary["covering"]
        cov = cov if isinstance(cov, list) else [cov]
        return "<rotleak.Covering %s>" % ", ".join("%s: zero measure %.3g" % (c["omega"], c["zero_measure"])
                                                    for c in cov)


def covering(omega, delta="1e-7", lam="0.01", d="2", r="1", resolution=1000):
    """The MUPO covering f_L(s) of the leak during a bouncing-ball crossing, for one omega or a list
    of them, at one delta or a list (every omega at every delta), exactly as ``rotleak covering``."""
    omegas = [omega] if not isinstance(omega, (list, tuple)) else list(omega)
    deltas = [delta] if not isinstance(delta, (list, tuple)) else list(delta)
    doc, profile, segments = _module().covering([_text(o) for o in omegas], [_text(x) for x in deltas], _text(lam),
                                                _text(d), _text(r), int(resolution))
    return Covering(json.loads(doc), profile, segments)
