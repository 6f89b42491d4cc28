#!/usr/bin/python3
"""Checks that includes only point down the layers of the design:

    numeric <- geometry <- leak <- sim <- io <- analysis <- output <- verify <- run <- cli (and bench, tests)

A file may include files of its own layer and of the layers below it, never above. The layers live in
four top-level folders, which are layers in the same order:

    src (numeric .. io) <- analysis (analysis, and output: the writers of its results) <- verify <- app (run, cli)

so no include runs from a folder up to a later one (checked too, and named as such). Inside src/sim the
folders are layers of their own, in the same way:

    sim/model <- sim/kernel <- sim/tally <- sim/gpu <- sim/engine

(the scene and one particle's physics; the vectorised kernel's plain interface; the tallies, the f_c
observer and the survival curve; the GPU engine's launches; the engines that run blocks and lines). The Python package is layered
too: rotleak.readers <- rotleak (its __init__) <- rotleak.plot, checked on its relative imports.
Prints every violation (file, line, include, the two layers) and exits 1 if there is one; prints a
one-line summary otherwise. Reads .hpp, .cpp, .h and .ipp files (the kernel's body is an .ipp) and
the package's .py files. Run from
anywhere: /usr/bin/python3 scripts/check_layers.py [ROOT] (ROOT: the repository, by default the one holding
this script; the test runs it on a small tree of its own to see an upward include fail).
"""
import os
import re
import sys

LAYERS = ["numeric", "geometry", "leak", "sim", "io", "analysis", "output", "verify", "run", "cli"]
# where each layer lives (relative to the repository root); the longest matching prefix decides
DIRS = {
    "src/numeric": "numeric", "src/geometry": "geometry", "src/leak": "leak", "src/sim": "sim", "src/io": "io",
    "analysis": "analysis", "analysis/output": "output", "verify": "verify", "app/run": "run", "app/cli": "cli",
    "bench": "cli", "tests": "cli", "python": "cli",
}
# the top-level folders, lowest first, and the layers each holds (bench, tests and python sit above all)
FOLDERS = [("src", {"numeric", "geometry", "leak", "sim", "io"}), ("analysis", {"analysis", "output"}),
           ("verify", {"verify"}), ("app", {"run", "cli"})]


def folder_of(layer):
    """The top-level folder of a layer (None for the users above them all: bench, tests, python)."""
    for name, layers in FOLDERS:
        if layer in layers:
            return name
    return None
# src/sim's folders, lowest first: an include from one to a later one points up
SIM_FOLDERS = ["model", "kernel", "tally", "gpu", "engine"]
# the Python package's modules, lowest first (the build backend imports none of them)
PY_LAYERS = ["readers", "__init__", "plot"]
PY_IMPORT = re.compile(r"^\s*from\s+(\.+)([\w.]*)\s+import\s+([\w, ()]+)")
# generated headers and the layer they belong to
GENERATED = {"version.hpp": "numeric"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def layer_of_include(path, includer_dir):
    if path in GENERATED:
        return GENERATED[path]
    for prefix in sorted(DIRS, key=len, reverse=True):  # analysis/output before analysis
        short = prefix.split("/", 1)[1] if prefix.startswith(("src/", "app/")) else prefix
        if path.startswith(short + "/") or path.startswith(prefix + "/"):
            return DIRS[prefix]
    # a bare name is a file beside the includer (tests/tiers.hpp)
    return DIRS.get(includer_dir)


def sim_folder(path):
    """The src/sim folder of an include ("sim/tally/tally.hpp") or a file (relative to src/sim); None if none."""
    parts = path.split("/")
    return parts[1] if len(parts) > 2 and parts[0] == "sim" and parts[1] in SIM_FOLDERS else None


def source_files(root, d):
    """The C++ files of layer directory d, with src/sim's folders walked (relative paths)."""
    full = os.path.join(root, d)
    out = []
    for sub, dirs, names in os.walk(full):
        dirs.sort()
        if sub != full and d != "src/sim":
            dirs[:] = []
            continue  # only src/sim has folders of its own (analysis/output is a layer of its own)
        out += [os.path.relpath(os.path.join(sub, n), root) for n in sorted(names) if n.endswith((".hpp", ".cpp", ".h", ".ipp"))]
    return out


def check_python(root, bad):
    """rotleak.readers <- rotleak <- rotleak.plot: a module's relative imports point down or sideways."""
    package = os.path.join(root, "python", "rotleak")
    checked = 0
    for sub, dirs, names in os.walk(package):
        dirs[:] = sorted(x for x in dirs if x != "__pycache__")
        for name in sorted(n for n in names if n.endswith(".py")):
            rel = os.path.relpath(os.path.join(sub, name), package)
            mine = "plot" if rel.startswith("plot" + os.sep) else name[:-3]
            if mine not in PY_LAYERS:
                continue
            checked += 1
            with open(os.path.join(sub, name), encoding="utf-8") as f:
                for no, line in enumerate(f, 1):
                    m = PY_IMPORT.match(line)
                    if not m:
                        continue
                    dots, module, names_ = len(m.group(1)), m.group(2), m.group(3)
                    if mine == "plot" and dots == 1:
                        continue  # inside rotleak.plot
                    target = module.split(".")[0] if module else "__init__"
                    if target not in PY_LAYERS:
                        if target == "_rotleak" or (target == "__init__" and "_rotleak" in names_) or target == "_version":
                            continue  # the compiled module and the generated version: below everything
                        bad.append(f"python/rotleak/{rel}:{no}: imports .{module} ({target}), in no known layer")
                    elif PY_LAYERS.index(target) > PY_LAYERS.index(mine):
                        bad.append(f"python/rotleak/{rel}:{no}: imports .{module or ''} ({target}) from {mine}, "
                                   "a lower layer")
    return checked


def folders_follow_layers():
    """The folders hold the layers in order: an include that keeps to the layers keeps to the folders."""
    order = [f for f, _ in FOLDERS]
    held = [order.index(folder_of(x)) for x in LAYERS if folder_of(x)]
    return held == sorted(held)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    bad, files, includes = [], 0, 0
    if not folders_follow_layers():
        bad.append(f"the folders ({FOLDERS}) do not hold the layers ({LAYERS}) in order")
    for d, layer in DIRS.items():
        if not os.path.isdir(os.path.join(root, d)):
            continue
        for rel in source_files(root, d):
            files += 1
            mine = sim_folder(os.path.relpath(rel, "src")) if d == "src/sim" else None
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                for no, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    includes += 1
                    target = layer_of_include(m.group(1), d)
                    folder = sim_folder(m.group(1))
                    if target is None:
                        bad.append(f"{rel}:{no}: \"{m.group(1)}\" is in no known layer")
                    elif LAYERS.index(target) > LAYERS.index(layer):
                        mine_f, theirs = folder_of(layer), folder_of(target)
                        across = f", and from {mine_f}/ up to {theirs}/" if mine_f and mine_f != theirs else ""
                        bad.append(f"{rel}:{no}: includes \"{m.group(1)}\" ({target}) from {layer}, a lower layer{across}")
                    elif d == "src/sim" and target == "sim" and (mine is None or folder is None):
                        bad.append(f"{rel}:{no}: \"{m.group(1)}\": every file of src/sim lives in one of its folders "
                                   f"({', '.join(SIM_FOLDERS)})")
                    elif mine and folder and SIM_FOLDERS.index(folder) > SIM_FOLDERS.index(mine):
                        bad.append(f"{rel}:{no}: includes \"{m.group(1)}\" (sim/{folder}) from sim/{mine}, a lower "
                                   "folder")
    modules = check_python(root, bad)
    for b in bad:
        print(b)
    print(f"{files} files, {includes} project includes, {modules} Python modules, {len(bad)} pointing up "
          f"(layers, lowest first: {' <- '.join(LAYERS)}; folders: {' <- '.join(f for f, _ in FOLDERS)}; "
          f"inside sim: {' <- '.join(SIM_FOLDERS)}; "
          f"Python: {' <- '.join(PY_LAYERS)})")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
