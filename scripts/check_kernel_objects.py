#!/usr/bin/python3
"""The vectorised kernel's objects must not define a weak (inline, template) symbol.

The kernel translation units (src/sim/kernel/simd_engine.cpp for AVX2, src/sim/kernel/simd_avx512.cpp for AVX-512) are
compiled for those instruction sets alone, and they instantiate the shared physics formulas
(src/geometry/formulas.hpp, src/leak/leak_formulas.hpp) on their own pack types. Were one of them to emit
a weak copy of an inline function that scalar code also uses (a formula instantiated on double, say),
the linker could keep that vector copy for the whole program, and a CPU without AVX-512 would fault in
scalar code. So: no weak symbols there, but the personality routine's reference (DW.ref.*).

Second, the kernel's hot loop must be one function: GCC 12 once left the pack's own operators and lambdas,
next_hit and the leak tests as calls inside it (a call passes its packs through memory), and whether it did
changed with any function added elsewhere in the file. The collision step (lane_step, written once for every
table: src/sim/kernel/simd_lanes.ipp; one instantiation for the stadium, one for any table, each with and without
KeepLast) and flights_kernel are [[gnu::flatten]]; the step's loop (run_lanes) calls the step. run_kernel,
run_table_kernel, run_lanes, flights_kernel and the step instantiations call nothing of the kernel's own but
run_lanes and a step, only SLEEF and libm's or the core's own atan2 (near an edge; formula::atan2_scalar is out of
line in numeric/atan2.cpp, not the kernel's).

usage: check_kernel_objects.py OBJECT...   (exit 1, naming each weak symbol or call left, when any is found)
       check_kernel_objects.py --selftest  (the call finder on a canned disassembly, which it must flag)
"""
import re
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


HOT = ("run_kernel(", "run_table_kernel(", "flights_kernel(", "::lane_step<", "::run_lanes<")
SELFTEST = """0000000000000000 <rotleak::simd::avx2_kernel::run_kernel(rotleak::simd::KernelScene const&)>:
   0:	call   10 <rotleak::simd::avx2_kernel::(anonymous namespace)::next_hit(rotleak::simd::KernelScene const&)>
   5:	call   0 <rotleak::simd::avx2_kernel::run_kernel(rotleak::simd::KernelScene const&)+0x5>
			6: R_X86_64_PLT32	Sleef_atan2d4_u35avx2-0x4
"""


def hot_calls(disassembly):
    """(function, target) of every call from a hot function to a function of the kernel's own but a step."""
    found, current, pending = [], None, None
    for line in disassembly.splitlines():
        head = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if head:
            current = head.group(1) if any(h in head.group(1) for h in HOT) else None
            continue
        if current is None:
            continue
        reloc = re.search(r"R_X86_64_\w+\s+(\S+)", line)
        if reloc and pending is not None:
            pending = None  # the call's real target is the relocation's symbol (SLEEF, a callback's PLT)
            continue
        if pending is not None:
            found.append(pending)
            pending = None
        call = re.search(r"\bcall\s+[0-9a-f]+ <(.*)>", line)
        if call:
            target = re.sub(r"\+0x[0-9a-f]+$", "", call.group(1))
            if "(anonymous namespace)::" in target and "::lane_step<" not in target and "::run_lanes<" not in target:
                pending = (current, target)
    if pending is not None:
        found.append(pending)
    return found


def main(paths):
    if paths == ["--selftest"]:
        got = hot_calls(SELFTEST)
        if len(got) == 1 and "next_hit" in got[0][1]:
            print("check_kernel_objects.py --selftest: the canned call to next_hit is found, SLEEF's is not")
            return 0
        print("check_kernel_objects.py --selftest: found %s" % got)
        return 1
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
    calls = 0
    for p in paths:
        text = subprocess.run(["objdump", "-dr", "-C", "--no-show-raw-insn", p], check=True, capture_output=True,
                              text=True).stdout
        for fn, target in hot_calls(text):
            print(f"{p}: {fn[:80]} calls {target[:100]}: not inlined into the hot loop")
            calls += 1
    if calls:
        print(f"{calls} call(s) left in the kernel's hot loop")
        return 1
    print(f"{len(paths)} kernel object(s), no weak symbols, the hot loop one function (no call of its own but a step)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
