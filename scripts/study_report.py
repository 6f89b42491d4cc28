#!/usr/bin/python3
"""Writes DOCS/README.md from a reproduce_study.sh output directory: per panel its command, its
pictures (copied to DOCS/img/) and a table; the published-vs-ours table (data/literature/).

Usage: study_report.py STUDY_DIR DOCS_DIR PARTICLES SECONDS"""
import csv
import json
import os
import platform
import shutil
import sys
from fractions import Fraction


def literature(name):
    with open(os.path.join("data", "literature", name), newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def fmt(x, digits=4):
    return "-" if x in (None, "") else "%.*g" % (digits, float(x))


def alpha_text(a):
    """alpha as value +- stat. +- syst. (the window systematic; "?" when kappa's windows do not resolve it),
    or its upper bound."""
    if a["value"] is not None:
        syst = a.get("systematic")
        return "%.3g +- %.2g (stat.) +- %s (syst.)" % (a["value"], a["error"], "%.2g" % syst if syst is not None
                                                      else "?")
    if a["upper_bound"] is not None:
        return "< %.2g" % a["upper_bound"]
    return "-"


def same_omega(a, b):
    try:
        return Fraction(a) == Fraction(b)
    except ValueError:
        return a == b


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.machine()


def main():
    if len(sys.argv) != 5:
        sys.exit("usage: study_report.py STUDY_DIR DOCS_DIR PARTICLES SECONDS")
    study, docs, particles, seconds = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    img = os.path.join(docs, "img")
    os.makedirs(img, exist_ok=True)
    panels = []
    with open(os.path.join("data", "study", "panels.tsv")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                name, title, args = line.rstrip("\n").split("\t")
                panels.append((name, title, args))
    out = ["# The study, panel by panel", "",
           "Written by `scripts/reproduce_study.sh%s` (%d lines a point: importance sampling "
           "`ensemble.sampling = \"mupo\"` with fast-forward and population splitting `run.splitting = true`, "
           "docs/model.md \"Deep tails\"; on %s, %d cores; this invocation took %d s, complete points being skipped on a "
           "re-run; SIM_TOTAL). Each panel is one "
           "`rotleak scan` of `data/study/study.toml` (d = 2, r = 1, leak width 0.01 at s_L = 0) over the values "
           "in `data/study/panels.tsv`; every point is an ordinary run directory, so `rotleak fit` re-analyses "
           "and `rotleak plot` redraws it." % (" --quick" if particles <= 100000 else "", particles,
                                                  cpu_model(), os.cpu_count() or 0, seconds), ""]
    found = {}
    sim_total = 0.0
    for name, title, args in panels:
        d = os.path.join(study, name)
        with open(os.path.join(d, "scan.json")) as f:
            doc = json.load(f)
        keys = [a["key"] for a in doc["axes"]]
        sim = sum(p.get("wall_seconds") or 0 for p in doc["points"])
        sim_total += sim
        out += ["## %s" % title, "", "`rotleak scan data/study/study.toml %s --particles %d --set "
                "ensemble.sampling=mupo --set run.fast_forward=true --set run.splitting=true --out %s` (%d points, "
                "%.0f s of simulation: the "
                "sum of the points' wall times)" % (args, particles, d, len(doc["points"]), sim), ""]
        for png in sorted(p for p in os.listdir(d) if p.endswith(".png")):
            target = "%s_%s" % (name, png)
            shutil.copyfile(os.path.join(d, png), os.path.join(img, target))
            out += ["![%s: %s](img/%s)" % (name, png, target), ""]
        if name == "stationary":  # f_c of each leak, over the whole run and over t >= 2000
            for p in doc["points"]:
                fc = os.path.join(d, "points", p["point"], "fc.png")
                if os.path.exists(fc):
                    target = "stationary_fc_%s.png" % p["point"]
                    shutil.copyfile(fc, os.path.join(img, target))
                    out += ["![f_c, %s](img/%s)" % (p["point"], target), ""]
        cov = os.path.join(study, "covering_" + name, "f_L.png")
        if os.path.exists(cov):
            shutil.copyfile(cov, os.path.join(img, "%s_f_L.png" % name))
            out += ["f_L at delta = 1e-7 (`rotleak covering`):", "", "![f_L](img/%s_f_L.png)" % name, ""]
        out += ["| " + " | ".join(k.split(".")[-1] for k in keys) +
                " | kappa | alpha | tail | regime | tail gone by | tau1 | tau2 |",
                "|" + "---|" * (len(keys) + 7)]
        for p in doc["points"]:
            k = p["kappa"]
            kap = "%.5g +- %.1g +- %.1g" % (k["value"], k["error"], k.get("window_systematic") or 0) if k["value"] else "-"
            t = p["tail"]
            pred = p["predicted"]
            out.append("| " + " | ".join(p["values"][key] for key in keys) + " | %s | %s | %s | %s | %s | %s | %s |" % (
                kap, alpha_text(p["alpha"]), t["class"], t["regime"], fmt(t["tail_end"], 5), fmt(pred["tau1"], 6),
                fmt(pred["tau2"], 6)))
            found[(name, tuple(p["values"].get(key) for key in keys))] = p
        out.append("")
    lnc = os.path.join(study, "covering_ln19", "f_L.png")
    if os.path.exists(lnc):
        shutil.copyfile(lnc, os.path.join(img, "ln19_f_L.png"))
        out += ["## The covering of ln(19) at delta = 1e-7 and 1e-9", "", "![f_L of ln(19)](img/ln19_f_L.png)", ""]

    out += ["## Published vs ours", "", "| quantity | published | ours | diff |", "|---|---|---|---|"]
    for row in literature("stationary_leak_table.csv"):
        p = found.get(("stationary", (row["s_L"],)))
        if not p:
            continue
        for q in ("kappa", "alpha"):
            ours = p[q]["value"]
            pub = float(row[q])
            diff = "%+.1f%%" % (100 * (ours / pub - 1)) if ours else "-"
            shown = alpha_text(p[q]) if q == "alpha" else "%.4g +- %.1g" % (ours, p[q]["error"]) if ours else "-"
            out.append("| %s, s_L = %s | %g | %s | %s |" % (q, row["s_L"], pub, shown, diff))
    for row in literature("rotating.csv"):
        if row["quantity"] != "alpha":
            continue
        p = next((v for (panel, vals), v in found.items() if vals and vals[0] and same_omega(vals[0], row["omega"])
                  and panel in ("q_minus_1_over_q", "approximants_of_1")), None)
        if not p:
            continue
        pub = ("< " if row["kind"] == "bound" else "") + row["value"]
        ours = p["alpha"]["value"]
        diff = "%+.1f%%" % (100 * (ours / float(row["value"]) - 1)) if ours and row["kind"] == "value" else "-"
        out.append("| alpha, omega = %s | %s | %s | %s |" % (row["omega"], pub, alpha_text(p["alpha"]), diff))
    out += ["", "Regime boundaries for lambda = 0.01 (published ~4e-4 and ~1e-2): `rotleak regimes`, see "
            "docs/guide/scans.md. Tails below what the lines resolve are bounds, not values: an upper bound holds over the times "
            "where at least 100 effective lines remain.", "",
            "Reading the regimes: the class is measured, never inferred from omega. An omega just off a simple "
            "rational, 1 - 1e-4 or 4/7 + 1/70000, moves the leak, seen from a bouncing-ball orbit sampling it every "
            "2r, by a slow drift. It then behaves like a slow leak: a tail that forms and is swept away, so it is "
            "classed `low`. `undecided` marks a persistent tail whose removal could not have been seen by t_max.", ""]
    out[2] = out[2].replace("SIM_TOTAL", "the points' simulations took %.0f s (%.1f h) in all, the sum of their wall "
                            "times on this machine" % (sim_total, sim_total / 3600))
    full = os.path.join(docs, "full", "README.md")
    if particles <= 100000 and os.path.exists(full):
        out.insert(3, "The full run (10^6 lines a point) is in [full/README.md](full/README.md).\n")
    os.makedirs(docs, exist_ok=True)
    tmp = os.path.join(docs, "README.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(out))
    os.replace(tmp, os.path.join(docs, "README.md"))
    print("wrote " + os.path.join(docs, "README.md"))


if __name__ == "__main__":
    main()
