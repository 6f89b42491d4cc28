#!/usr/bin/env python3
"""Checks that includes only point down the layers of the design:

    numeric <- geometry <- leak <- sim <- analysis <- io <- verify <- run <- cli (and bench, tests)

A file may include files of its own layer and of the layers below it, never above. Prints every
violation (file, line, include, the two layers) and exits 1 if there is one; prints a one-line
summary otherwise. Reads .hpp, .cpp, .h and .ipp files (the kernel's body is an .ipp). Run from
anywhere: python3 scripts/check_layers.py [ROOT] (ROOT: the repository, by default the one holding
this script; the test runs it on a small tree of its own to see an upward include fail).
"""
import os
import re
import sys

LAYERS = ["numeric", "geometry", "leak", "sim", "analysis", "io", "verify", "run", "cli"]
# where each layer lives (relative to the repository root)
DIRS = {
    "src/numeric": "numeric", "src/geometry": "geometry", "src/leak": "leak", "src/sim": "sim",
    "analysis": "analysis", "src/io": "io", "verify": "verify", "src/run": "run", "src/cli": "cli",
    "bench": "cli", "tests": "cli", "python": "cli",
}
# generated headers and the layer they belong to
GENERATED = {"version.hpp": "numeric"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def layer_of_include(path, includer_dir):
    if path in GENERATED:
        return GENERATED[path]
    for prefix, layer in DIRS.items():
        short = prefix[4:] if prefix.startswith("src/") else prefix
        if path.startswith(short + "/") or path.startswith(prefix + "/"):
            return layer
    # a bare name is a file beside the includer (tests/tiers.hpp)
    return DIRS.get(includer_dir)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    bad, files, includes = [], 0, 0
    for d, layer in DIRS.items():
        full = os.path.join(root, d)
        if not os.path.isdir(full):
            continue
        for name in sorted(os.listdir(full)):
            if not name.endswith((".hpp", ".cpp", ".h", ".ipp")):
                continue
            files += 1
            with open(os.path.join(full, name), encoding="utf-8") as f:
                for no, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    includes += 1
                    target = layer_of_include(m.group(1), d)
                    if target is None:
                        bad.append(f"{d}/{name}:{no}: \"{m.group(1)}\" is in no known layer")
                    elif LAYERS.index(target) > LAYERS.index(layer):
                        bad.append(f"{d}/{name}:{no}: includes \"{m.group(1)}\" ({target}) from {layer}, a lower layer")
    for b in bad:
        print(b)
    print(f"{files} files, {includes} project includes, {len(bad)} pointing up "
          f"(layers, lowest first: {' <- '.join(LAYERS)})")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
