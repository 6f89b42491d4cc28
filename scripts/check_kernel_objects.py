#!/usr/bin/env python3
"""The vectorised kernel's objects must not define a weak (inline, template) symbol.

The kernel translation units (src/sim/kernel/simd_engine.cpp for AVX2, src/sim/kernel/simd_avx512.cpp for AVX-512) are
compiled for those instruction sets alone, and they instantiate the shared physics formulas
(src/geometry/formulas.hpp, src/leak/leak_formulas.hpp) on their own pack types. Were one of them to emit
a weak copy of an inline function that scalar code also uses (a formula instantiated on double, say),
the linker could keep that vector copy for the whole program, and a CPU without AVX-512 would fault in
scalar code. So: no weak symbols there, but the personality routine's reference (DW.ref.*).

usage: check_kernel_objects.py OBJECT...   (exit 1, naming each weak symbol, when any is found)
"""
import subprocess
import sys


def weak_symbols(path):
    out = subprocess.run(["nm", "-C", path], check=True, capture_output=True, text=True).stdout
    found = []
    for line in out.splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3 and parts[1] in ("W", "w", "V", "v", "u") and not parts[2].startswith("DW.ref."):
            found.append(parts[2])
    return found


def main(paths):
    if not paths:
        print("check_kernel_objects.py: no object files given", file=sys.stderr)
        return 2
    bad = 0
    for p in paths:
        for sym in weak_symbols(p):
            print(f"{p}: weak symbol {sym}")
            bad += 1
    if bad:
        print(f"{bad} weak symbol(s) in the kernel objects: a vector copy could replace the scalar code's")
        return 1
    print(f"{len(paths)} kernel object(s), no weak symbols")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
