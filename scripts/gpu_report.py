#!/usr/bin/python3
"""Writes docs/performance.md's GPU table from bench_gpu's output (the JSON line it prints last; docs/output.md,
"bench_gpu JSON"), as scripts/gpu_check.sh saves it on the device's machine (OUT/bench_gpu.txt).

    /usr/bin/python3 scripts/gpu_report.py OUT/bench_gpu.txt [--doc docs/performance.md] [--date YYYY-MM-DD]

Replaces the part of the document between the markers below with: the card, the engine against the plain
one-thread-a-particle loop and the CPU engine per scene (collisions a second, their ratio, the wall time of the same
particles, both kernels' registers and blocks a multiprocessor), the engine's kernel in each register cap, the FP64
limit, and the issue's targets (the engine at least twice the plain loop on each scene; 9e10 collisions a second on
s_L = 0 and 10^10 quick-start particles with f_c in 15 s, on an H100) with whether this run met them. Nothing else in
the document is touched.
"""
import argparse
import datetime
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BEGIN = "<!-- gpu_report.py: begin (generated: edit scripts/gpu_report.py, not this part) -->"
END = "<!-- gpu_report.py: end -->"


def read_bench(path):
    """The last line of bench_gpu's output that parses as JSON."""
    with open(path) as f:
        lines = [l for l in f.read().splitlines() if l.startswith("{")]
    if not lines:
        sys.exit(f"gpu_report: {path} holds no JSON line (bench_gpu prints one last)")
    return json.loads(lines[-1])


def table(b, date):
    rows = ["| scene | engine coll/s | plain coll/s | engine / plain | engine s | plain s | CPU coll/s | "
            "engine / CPU | engine registers, blocks/SM | plain registers, blocks/SM |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for s in b["scenes"]:
        rows.append(f"| {s['scene']} | {s['engine_rate']:.3g} | {s['plain_rate']:.3g} | {s['ratio']:.2f} | "
                    f"{s['engine_seconds']:.2f} | {s['plain_seconds']:.2f} | {s['cpu_rate']:.3g} | "
                    f"{s['engine_rate'] / s['cpu_rate']:.1f} | {s['engine_registers']}, {s['engine_blocks']} | "
                    f"{s['plain_registers']}, {s['plain_blocks']} |")
    caps = ["| scene | blocks/SM asked | collisions/s | registers | blocks/SM |", "|---|---|---|---|---|"]
    for s in b["scenes"]:
        for c in s.get("kernel_caps", []):
            caps.append(f"| {s['scene']} | {c['min_blocks']} | {c['rate']:.3g} | {c['registers']} | {c['blocks']} |")
    by = {s["scene"]: s for s in b["scenes"]}
    met = []
    for name in ("s_L = 0", "omega = 2/3", "quick-start with f_c"):
        if name in by:
            r = by[name]["ratio"]
            met.append(f"- engine / plain on {name}: {r:.2f} ({'met' if r >= 2 else 'NOT met'}: at least 2)")
    if "s_L = 0" in by:
        rate = by["s_L = 0"]["engine_rate"]
        met.append(f"- s_L = 0: {rate:.3g} collisions/s ({'met' if rate >= 9e10 else 'NOT met'}: 9e10 on an H100)")
    if "quick-start with f_c" in by:
        q = by["quick-start with f_c"]
        per_particle = q["engine_seconds"] / b["particles"]
        met.append(f"- 10^10 quick-start particles with f_c at this rate: {per_particle * 1e10:.1f} s "
                   f"({'met' if per_particle * 1e10 <= 15 else 'NOT met'}: 15 s on an H100)")
    head = (f"`scripts/gpu_check.sh run` on {b['device']} ({date}), bench_gpu {b['particles']} particles a scene, "
            f"{b['rounds']} interleaved rounds (medians); the report written by "
            f"`/usr/bin/python3 scripts/gpu_report.py OUT/bench_gpu.txt`.")
    limit = (f"FP64 peak {b['fp64_peak']:.3g} FLOP/s; at 100 FP64 operations a collision, "
             f"{b['limit_at_100_flops']:.3g} collisions/s.")
    return "\n".join([head, "", *rows, "", "The engine's kernel alone, by register cap:", "", *caps, "", limit, "",
                      "Against the targets:", "", *met])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bench")
    ap.add_argument("--doc", default=os.path.join(ROOT, "docs", "performance.md"))
    ap.add_argument("--date", default=datetime.date.today().isoformat())
    a = ap.parse_args()
    b = read_bench(a.bench)
    with open(a.doc) as f:
        doc = f.read()
    if BEGIN not in doc or END not in doc:
        sys.exit(f"gpu_report: {a.doc} lacks the markers {BEGIN!r} and {END!r}")
    before, rest = doc.split(BEGIN, 1)
    _, after = rest.split(END, 1)
    tmp = a.doc + ".tmp"
    with open(tmp, "w") as f:
        f.write(before + BEGIN + "\n" + table(b, a.date) + "\n" + END + after)
    os.replace(tmp, a.doc)
    print(f"gpu_report: {a.doc}: the GPU table from {b['device']}")


if __name__ == "__main__":
    main()
