#!/usr/bin/python3
"""Writes docs/performance.md's current table from bench_scale's output: the kernel against the plain loop and
against its own ceiling, for each kernel width this CPU runs, in one run per width.

    /usr/bin/python3 scripts/performance_report.py [--build build] [--particles 2000000] [--rounds 3] [--threads 2]
                                          [--from JSON ...] [--doc docs/performance.md]

bench_scale (bench/bench_scale.cpp) writes its figures as JSON (its fifth argument; docs/output.md, "bench_scale
JSON"); this script runs it for 8 lanes (where the CPU has AVX-512) and 4, or reads the files given with --from,
and replaces the part of the document between the markers below with the table, the command and the machine.
Nothing else in the document is touched. The figures are ratios measured in one run (to the plain loop compiled
into the same binary, to the kernel's flights alone), never absolute rates, because the machines are shared.
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BEGIN = "<!-- performance_report.py: begin (generated: edit scripts/performance_report.py, not this part) -->"
END = "<!-- performance_report.py: end -->"


def machine():
    """The CPU's model name and the cores this process may use."""
    model = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return "%s, %d cores" % (model, len(os.sched_getaffinity(0)))


def run_bench(build, particles, rounds, threads, lanes):
    """bench_scale's JSON for one kernel width (None where the CPU does not run that width)."""
    exe = os.path.join(build, "bench", "bench_scale")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.json")
        cmd = [exe, str(particles), str(rounds), str(threads), str(lanes), out]
        print("running:", " ".join(cmd[:-1]), file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True, stdout=sys.stderr)
        with open(out) as f:
            doc = json.load(f)
    return doc if doc.get("lanes") == lanes else None


def shares(doc):
    """Per scene: its ratio to the plain loop, its share of the ceiling with draws (the median of its rounds' engine
    rate over the ceiling measured beside the same round), its share of s_L = 0 (ratio over s_L = 0's ratio)."""
    first = doc["scenes"][0]["ratio"]
    return [(s["scene"], s["ratio"], s["ceiling_share"], s["ratio"] / first) for s in doc["scenes"]]


def render(docs, command):
    """The generated part of docs/performance.md for bench_scale's JSON documents (one per width)."""
    lines = [BEGIN, "", "## The kernel against its ceiling (current)", ""]
    lines.append("`%s`, on %s; one run per width, each figure the median of its rounds. The ceiling is the "
                 "kernel's own flights (next hit and reflection, `simd::flights_only`) with the draws every particle "
                 "needs, measured beside every round of every scene; a scene's share of it (the median of its "
                 "rounds' rate over the ceiling of the same round) says how much of the kernel's physics the run "
                 "gets, its share of s_L = 0 what a moving leak or f_c costs beside a fixed leak." % (command, machine()))
    lines.append("")
    head = "| scene |"
    rule = "|---|"
    for d in docs:
        w = d["lanes"]
        head += " ratio to plain (%d lanes) | share of the ceiling | share of s_L = 0 |" % w
        rule += "---|---|---|"
    lines += [head, rule]
    rows = [shares(d) for d in docs]
    for i in range(len(rows[0])):
        line = "| %s |" % rows[0][i][0]
        for r in rows:
            _, ratio, ceil, first = r[i]
            line += " %.2f | %.0f%% | %.0f%% |" % (ratio, 100 * ceil, 100 * first)
        lines.append(line)
    lines.append("")
    for d in docs:
        fl, dr = d["ceiling_flights"]["ratio"], d["ceiling_with_draws"]["ratio"]
        lines.append("- %d lanes: flights alone %.2fx the plain loop; with the draws %.2fx (%.1f%% of flights alone; "
                     "the draws %.0f ns a particle per thread, %.0f ns one at a time through the scalar core); checkpoints "
                     "every 0.2 s on omega = 2/3 cost %+.1f%% wall time." %
                     (d["lanes"], fl, dr, 100 * d["ceiling_with_draws"]["share_of_flights"],
                      d["ceiling_with_draws"]["draw_ns_per_particle"],
                      d["ceiling_with_draws"].get("scalar_draw_ns_per_particle", float("nan")),
                      100 * d["checkpoint_overhead"]))
    lines += ["", END]
    return "\n".join(lines)


def replace_section(text, section):
    """The document with its generated part replaced (or added after its first paragraph, when missing)."""
    if BEGIN in text and END in text:
        a = text.index(BEGIN)
        b = text.index(END) + len(END)
        return text[:a] + section + text[b:]
    head, sep, rest = text.partition("\n## ")
    return head.rstrip("\n") + "\n\n" + section + "\n\n" + sep.lstrip("\n") + rest


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--particles", type=int, default=2000000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--from", dest="inputs", nargs="*", help="bench_scale JSON files instead of running it")
    ap.add_argument("--doc", default=os.path.join(ROOT, "docs", "performance.md"))
    a = ap.parse_args()
    if a.inputs:
        docs = []
        for path in a.inputs:
            with open(path) as f:
                docs.append(json.load(f))
        p, r, t = docs[0]["particles"], docs[0]["rounds"], docs[0]["threads"]
    else:
        docs = [d for d in (run_bench(a.build, a.particles, a.rounds, a.threads, w) for w in (8, 4)) if d]
        p, r, t = a.particles, a.rounds, a.threads
    if not docs:
        sys.exit("performance_report.py: bench_scale ran no kernel (this CPU lacks AVX2 and FMA)")
    command = "build/bench/bench_scale %d %d %d LANES" % (p, r, t)
    with open(a.doc) as f:
        text = f.read()
    out = replace_section(text, render(docs, command))
    tmp = a.doc + ".tmp"
    with open(tmp, "w") as f:
        f.write(out)
    os.replace(tmp, a.doc)
    print("performance_report.py: wrote %s (%s)" % (a.doc, ", ".join("%d lanes" % d["lanes"] for d in docs)))


if __name__ == "__main__":
    main()
