#!/usr/bin/python3
"""Mutation audit: apply deliberate errors one at a time, run the whole suite (ctest) against each, and
report which tests fail, how long the suite took and the most memory any test process used. Every
mutant is reverted (also on Ctrl-C or an error) and the build is rebuilt clean at the end.

Usage: /usr/bin/python3 scripts/mutation_audit.py [NAME ...]   (default: every mutation below)
       /usr/bin/python3 scripts/mutation_audit.py --list
Needs a configured build/ (bash scripts/build.sh). Takes about 2 minutes a mutant on 2 cores (a header
that everything includes: 5). Each mutant's ctest output is kept in build/mutation_audit/NAME.log.

A mutation is a (file, old text, new text) replacement: `old` must occur exactly once, so the audit
refuses to run on code that has moved away from what a mutation was written against.
"""
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(ROOT, "build")
LOGS = os.path.join(BUILD, "mutation_audit")  # each mutant's ctest output (--output-on-failure)

MUTATIONS = [
    {
        "name": "late-crossing",
        "what": "a tail whose crossing comes after t = 3000 is never called transient (persistent instead)",
        "file": "analysis/regimes.cpp",
        "edits": [
            ("  if (zero < c.t.size() && c.t[zero] < scene.t_max) {",
             "  if (zero < c.t.size() && c.t[zero] < scene.t_max && tc <= 3000) {"),
            ("  if (z - 6 > 3 * z_se && a < e) {", "  if (z - 6 > 3 * z_se && a < e && tc <= 3000) {"),
        ],
    },
    {
        "name": "fixedsum-low-word",
        "what": "FixedSum drops the lowest 64-bit word of every term it adds",
        "file": "src/numeric/fixed_sum.hpp",
        "edits": [
            ("      part[0] = lo, part[1] = hi, part[2] = 0;", "      part[0] = 0, part[1] = hi, part[2] = 0;"),
            ("      part[0] = lo << bit;", "      part[0] = 0;"),
        ],
    },
    {
        "name": "kappa-window-start",
        "what": "the kappa fit starts 50 time units after fit.kappa_window's start",
        "file": "analysis/run_summary.cpp",
        "edits": [
            ("fit_kappa(s.curve, scene.kappa_window.from, scene.kappa_window.to)",
             "fit_kappa(s.curve, scene.kappa_window.from + 50, scene.kappa_window.to)"),
        ],
    },
    {
        "name": "resume-skips-a-block",
        "what": "a resumed run counts the first block still to do as done without running it",
        "file": "src/run/pipeline.cpp",
        "edits": [
            ("  const IntervalSet todo = saved.done.complement_in(share_lo, share_hi);",
             "  if (!saved.done.empty()) {\n"
             "    const IntervalSet rest = saved.done.complement_in(share_lo, share_hi);\n"
             "    if (!rest.empty()) saved.done.insert(IntervalSet::range(rest.nth(0), rest.nth(0) + 1));\n"
             "  }\n"
             "  const IntervalSet todo = saved.done.complement_in(share_lo, share_hi);"),
        ],
    },
    {
        "name": "fast-forward-one-edge",
        "what": "the fast-forward looks for the stationary leak on one of the two straight edges only",
        "file": "src/sim/model/particle.hpp",
        "edits": [("        for (int parity = 1; parity <= 2; ++parity) {", "        for (int parity = 1; parity <= 1; ++parity) {")],
    },
    {
        "name": "kernel-window-edge",
        "what": "the vectorised kernel's top-edge leak window reaches 1e-4 further than the core's "
                "(a bit-identity failure: it must be reported in a line, in seconds, in bounded memory)",
        "file": "src/sim/kernel/simd_kernel.ipp",
        "edits": [("formula::in_x_window(h.x, V(S.lo[0][w]), V(S.hi[0][w]))",
                   "formula::in_x_window(h.x, V(S.lo[0][w]), V(S.hi[0][w] + 1e-4))")],
    },
]

# Run a command and print the peak resident memory of it and all its descendants (RUSAGE_CHILDREN).
RSS_WRAPPER = ("import resource, subprocess, sys\n"
               "r = subprocess.run(sys.argv[1:])\n"
               "print('MAXRSS_KB', resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n"
               "sys.exit(r.returncode)\n")


def build():
    r = subprocess.run(["cmake", "--build", BUILD, "-j", str(os.cpu_count() or 2)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stdout[-4000:] + r.stderr[-4000:])
        raise SystemExit("build failed")


def run_suite(log_name):
    t0 = time.time()
    r = subprocess.run([sys.executable, "-c", RSS_WRAPPER, "ctest", "-j", str(os.cpu_count() or 2), "--timeout", "600",
                        "--output-on-failure"], cwd=BUILD, capture_output=True, text=True)
    seconds = time.time() - t0
    os.makedirs(LOGS, exist_ok=True)
    with open(os.path.join(LOGS, log_name + ".log"), "w") as f:
        f.write(r.stdout + r.stderr)
    # "  221 - Leaks/FastForward.X/0_0_0  # GetParam() = (...) (Failed)": the name, then the verdict last
    failed = re.findall(r"^\s*\d+ - (\S+).*\((Failed|Timeout|SEGFAULT|Subprocess aborted|Exception|Not Run)\)\s*$",
                        r.stdout, re.M)
    times = {m.group(1): float(m.group(2)) for m in re.finditer(r"Test\s+#\d+: (\S+).*?\s([\d.]+) sec\s*$", r.stdout, re.M)}
    rss = re.search(r"MAXRSS_KB (\d+)", r.stderr)
    total = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
    if total and int(total.group(1)) != len(failed):
        print(f"  (ctest counts {total.group(1)} failures, {len(failed)} parsed: see {LOGS})", flush=True)
    return {
        "failed": [(name, why, times.get(name)) for name, why in failed],
        "seconds": seconds,
        "max_rss_mb": int(rss.group(1)) / 1024 if rss else None,
        "count": int(total.group(2)) if total else None,
    }


def apply(m):
    path = os.path.join(ROOT, m["file"])
    with open(path) as f:
        original = f.read()
    text = original
    for old, new in m["edits"]:
        n = text.count(old)
        if n != 1:
            raise SystemExit(f"{m['name']}: {m['file']} holds the text to mutate {n} times (expected once): {old!r}")
        text = text.replace(old, new)
    with open(path, "w") as f:
        f.write(text)
    return path, original


def main(argv):
    if "--list" in argv:
        for m in MUTATIONS:
            print(f"{m['name']}: {m['what']} ({m['file']})")
        return 0
    chosen = [m for m in MUTATIONS if not argv or m["name"] in argv]
    unknown = set(argv) - {m["name"] for m in MUTATIONS}
    if unknown:
        raise SystemExit("unknown mutation(s): " + ", ".join(sorted(unknown)) + "; --list names them")
    if not os.path.isdir(BUILD):
        raise SystemExit("no build/: run bash scripts/build.sh first")
    rows = []
    try:
        for m in chosen:
            path, original = apply(m)
            try:
                print(f"[mutation_audit] {m['name']}: {m['what']}", flush=True)
                build()
                res = run_suite(m["name"])
            finally:
                with open(path, "w") as f:
                    f.write(original)
            rows.append((m, res))
            names = ", ".join(n for n, _, _ in res["failed"]) or "NONE (the mutant survived)"
            print(f"  {len(res['failed'])} of {res['count']} tests fail; suite {res['seconds']:.0f} s, "
                  f"max RSS {res['max_rss_mb']:.0f} MB: {names}", flush=True)
    finally:
        build()  # the code as it is, again
    print("\n| mutation | what | tests that fail (time) | suite | max RSS |\n|---|---|---|---|---|")
    for m, res in rows:
        fails = "; ".join(f"{n} ({t:.1f} s)" if t is not None else n for n, _, t in res["failed"]) or "**none: survived**"
        print(f"| {m['name']} | {m['what']} | {fails} | {res['seconds']:.0f} s | {res['max_rss_mb']:.0f} MB |")
    return 1 if any(not res["failed"] for _, res in rows) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
