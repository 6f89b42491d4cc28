#!/usr/bin/python3
"""The omega atlas's report (scripts/atlas.sh): reads each set's scan (OUT/<set>/table.csv with pandas,
OUT/<set>/scan.json) and writes DOCS/README.md (the table: omega exact, Q, kappa, alpha +- stat +- syst,
C +- stat +- drift or, where t P is not flat, t P where the tail begins, tail class, regime, tail end and
the range the rule places it in), DOCS/atlas.csv (the same table) and the figures:
C against omega, C against Q (even and odd Q apart), the tail end against eps for the eps families, and
alpha against omega. Usage: atlas_report.py OUT DOCS PARTICLES SECONDS (SECONDS: the wall time of the
atlas.sh call)."""
import json
import math
import os
import sys
from fractions import Fraction

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas  # noqa: E402

SETS = "data/atlas/sets.tsv"


def sets():
    out = []
    with open(SETS, encoding="utf-8") as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            name, title, args = line.rstrip("\n").split("\t")
            out.append((name, title, args))
    return out


def rational(text):
    """The exact rational of an omega text, or None (an irrational, a near-rational sum)."""
    try:
        return Fraction(text)
    except ValueError:
        return None


def family(text):
    """(base rational, signed eps) of a near(x, e) text 'p/q+e' or 'p/q-e', else None."""
    for sign in ("+", "-"):
        base, _, eps = text.partition(sign)
        if eps and rational(base) is not None:
            try:
                return rational(base), (1 if sign == "+" else -1) * float(eps)
            except ValueError:
                return None
    return None


def big_q(omega, r=1):
    """Q: the denominator of 2 r omega mod 1 (docs/study/atlas/README.md)."""
    x = 2 * r * omega
    return (x - math.floor(x)).denominator


def rows_of(out, name):
    table = pandas.read_csv(os.path.join(out, name, "table.csv"), dtype={"leak.omega": str, "tail": str, "predicted_tail": str,
                                                                      "regime": str, "cf_2r_omega": str},
                            keep_default_na=False,
                            na_values={c: [""] for c in ["kappa", "kappa_err", "alpha", "alpha_err", "alpha_syst",
                                                         "alpha_bound", "tail_end", "tail_amplitude",
                                                         "tail_amplitude_err", "tail_amplitude_syst",
                                                         "predicted_amplitude", "predicted_tail_end"]})
    with open(os.path.join(out, name, "scan.json"), encoding="utf-8") as f:
        doc = json.load(f)
    seconds = sum(p.get("wall_seconds", 0) or 0 for p in doc["points"])
    rows = []
    for (_, t), p in zip(table.iterrows(), doc["points"]):
        scene = point_scene(out, name, p)
        w = t["leak.omega"]
        q = rational(w)
        fam = family(w)
        near = p["tail"].get("near_rational")
        amp = p["tail"].get("amplitude") or {}
        end_range = p["tail"].get("tail_end_range")
        fall = tail_fall(out, name, p, amp.get("from")) if fam else (None, None)
        rows.append({"set": name, "omega": w, "value": omega_value(w, t["cf_2r_omega"]),
                     "Q": big_q(q) if q is not None else (big_q(fam[0]) if fam else None),
                     "base": fam[0] if fam else None, "eps": fam[1] if fam else None,
                     "kappa": t["kappa"], "kappa_err": t["kappa_err"], "alpha": t["alpha"], "alpha_err": t["alpha_err"],
                     "alpha_syst": t["alpha_syst"], "alpha_bound": t["alpha_bound"], "C": t["tail_amplitude"],
                     "C_err": t["tail_amplitude_err"], "C_syst": t["tail_amplitude_syst"], "tail": t["tail"],
                     "regime": t["regime"], "tail_end": t["tail_end"],
                     "near": near["rational"] if near else "", "t_max": scene["run"]["t_max"],
                     "d": scene["stadium"]["d"], "r": scene["stadium"]["r"], "width": scene["leak"]["width"],
                     "pred_tail": t["predicted_tail"], "pred_C": t["predicted_amplitude"],
                     "pred_end": t["predicted_tail_end"], "end_half": fall[0], "end_tenth": fall[1],
                     "height": amp.get("height"), "height_err": amp.get("height_error"), "from": amp.get("from"),
                     "end_lo": end_range[0] if end_range else None, "end_hi": end_range[1] if end_range else None})
    return rows, seconds


def omega_value(text, cf_2r_omega, r=1):
    """omega as a double: exact for rationals and near(x, e) sums, else from the scan's certified partial
    quotients of 2 r omega (8 of them: good to about 1e-8, plenty for a plot)."""
    q = rational(text)
    if q is not None:
        return float(q)
    fam = family(text)
    if fam:
        return float(fam[0]) + fam[1]
    terms = [int(a) for a in str(cf_2r_omega).split()]
    x = Fraction(terms[-1])
    for a in reversed(terms[:-1]):
        x = a + 1 / x
    return float(x) / (2 * r)


def tail_fall(out, name, point, start):
    """The measured end in the model's terms: the first times past `start` (the tail amplitude's `from`) where
    t P(t) falls to a half and to a tenth of its largest value past `start` (None: not before t_max)."""
    if not isnum(start):
        return None, None
    s = pandas.read_csv(os.path.join(out, name, "points", point["point"], "survival.csv"))
    s = s[s["t"] >= start]
    tp = s["t"] * s["P"]
    top = tp.max()
    half, tenth = s[tp < 0.5 * top]["t"], s[tp < 0.1 * top]["t"]
    return (float(half.iloc[0]) if len(half) else None), (float(tenth.iloc[0]) if len(tenth) else None)


def point_scene(out, name, point):
    """The scene a point ran (its summary.json): t_max, the stadium and the leak width."""
    path = os.path.join(out, name, "points", point["point"], "summary.json")
    with open(path, encoding="utf-8") as f:
        return json.load(f)["scene"]


def fmt(v, e=None, s=None, digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    out = "%.*g" % (digits, v)
    if e is not None and not (isinstance(e, float) and math.isnan(e)):
        out += " +- %.2g" % e
    if s is not None and not (isinstance(s, float) and math.isnan(s)):
        out += " +- %.2g" % s
    return out


def isnum(v):
    return v is not None and not (isinstance(v, float) and math.isnan(v))


def finish(fig, ax, path, xlabel, ylabel, title, logx=True):
    """Scales, labels, grid and legend of a figure's one panel; writes it to path."""
    if logx:
        ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figures(rows, docs):
    """Draws the figures the rows have data for; returns their file names."""
    drawn = []
    rat = [r for r in rows if r["set"] == "rationals"]
    have = [r for r in rat if isnum(r["C"])]
    if have:
        c_figures(rat, have, docs)
        drawn += ["C_vs_omega.png", "C_vs_Q.png"]
    fams = [r for r in rows if r["eps"] is not None]
    if fams:
        tail_end_figure(fams, docs)
        drawn.append("tail_end_vs_eps.png")
    if any(isnum(r["alpha"]) or isnum(r["alpha_bound"]) for r in rows):
        alpha_figure(rows, docs)
        drawn.append("alpha_vs_omega.png")
    return drawn


def c_figures(rat, have, docs):
    # C against omega, Q marked
    fig, ax = plt.subplots(figsize=(11, 4.8))
    sc = ax.scatter([r["value"] for r in have], [r["C"] for r in have], c=[math.log(r["Q"]) for r in have], s=14,
                    cmap="viridis")
    ax.errorbar([r["value"] for r in have], [r["C"] for r in have], yerr=[r["C_err"] for r in have], fmt="none",
                ecolor="0.6", lw=0.6, zorder=0)
    for r in have:
        if r["Q"] <= 5:
            ax.annotate("%s (Q=%d)" % (r["omega"], r["Q"]), (r["value"], r["C"]), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
    none = [r for r in rat if not isnum(r["C"])]
    ax.scatter([r["value"] for r in none], [min(r2["C"] for r2 in have) / 3] * len(none),
               marker="x", color="C3", s=12, label="no C (%d): tail not 1/t or not resolved" % len(none))
    fig.colorbar(sc, ax=ax, label="ln Q")
    finish(fig, ax, os.path.join(docs, "C_vs_omega.png"), "omega = p/q, q <= 30", "C  (P ~ C / t)",
           "tail amplitude against omega (colour: ln Q, Q the denominator of 2 r omega mod 1)", logx=False)
    # C against Q, even and odd apart
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for parity, marker, colour in ((0, "s", "C0"), (1, "o", "C3")):
        sel = [r for r in have if r["Q"] % 2 == parity]
        ax.errorbar([r["Q"] + (0.15 if parity else -0.15) for r in sel], [r["C"] for r in sel],
                    yerr=[r["C_err"] for r in sel], fmt=marker, ms=4, color=colour, lw=0.8,
                    label="%s Q" % ("even" if parity == 0 else "odd"))
    finish(fig, ax, os.path.join(docs, "C_vs_Q.png"), "Q", "C", "tail amplitude against Q (every p/q with q <= 30)")


def tail_end_figure(fams, docs):
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for k, base in enumerate(sorted({r["base"] for r in fams})):
        for sign, marker in ((1, "o"), (-1, "v")):
            sel = [r for r in fams if r["base"] == base and (r["eps"] > 0) == (sign > 0)]
            if not sel:
                continue
            ended = [r for r in sel if isnum(r["tail_end"])]
            ax.plot([abs(r["eps"]) for r in ended], [r["tail_end"] for r in ended], marker, color="C%d" % k,
                    label="%s %s eps" % (base, "+" if sign > 0 else "-"))
            open_ = [r for r in sel if not isnum(r["tail_end"]) and r["tail"] in ("persistent", "unresolved")]
            ax.plot([abs(r["eps"]) for r in open_], [r["t_max"] for r in open_], "^", color="C%d" % k, mfc="none")
    finish(fig, ax, os.path.join(docs, "tail_end_vs_eps.png"), "|eps| (omega = p/q + eps)",
           "tail end (open triangles: a tail still there at t_max)", "when a near-rational tail ends")


def alpha_figure(rows, docs):
    fig, ax = plt.subplots(figsize=(11, 4.8))
    for name, colour in (("rationals", "C0"), ("irrationals", "C2")):
        sel = [r for r in rows if r["set"] == name]
        val = [r for r in sel if isnum(r["alpha"])]
        ax.errorbar([r["value"] for r in val], [r["alpha"] for r in val],
                    yerr=[math.hypot(r["alpha_err"], r["alpha_syst"] if isnum(r["alpha_syst"]) else 0) for r in val],
                    fmt="o", ms=3, color=colour, lw=0.6, label="%s: alpha" % name)
        bnd = [r for r in sel if not isnum(r["alpha"]) and isnum(r["alpha_bound"])]
        ax.plot([r["value"] for r in bnd], [r["alpha_bound"] for r in bnd], "v", ms=4, color=colour, mfc="none",
                label="%s: upper bound" % name)
    finish(fig, ax, os.path.join(docs, "alpha_vs_omega.png"), "omega", "alpha", "alpha against omega", logx=False)


def measured_forms(r):
    """A tail was seen: a class other than none (unresolved: seen, alpha not resolved)."""
    return r["tail"] in ("persistent", "transient", "unresolved")


def end_check(r):
    """The predicted end against the measured bracket [end_lo, end_hi] (the rule's own error): the relative
    distance to the bracket, 0 inside it."""
    lo, hi, p = r["end_lo"], r["end_hi"], r["pred_end"]
    return 0.0 if lo <= p <= hi else (p / hi - 1 if p > hi else p / lo - 1)


def prediction_section(rows, docs):
    """The covering model (docs/model.md, "Predicting the tail from omega") against the atlas: C on exact
    rationals, the tail-forms verdict everywhere, the end on the eps families; the test half is the odd rows of
    atlas.csv (numbered from 1), the other half is where constants would be fitted (the model has none)."""
    lines = ["", "## The covering model against the atlas", "",
             "Predicted by `rotleak predict` (every point's summary.json `predicted.tail`, the scan table's "
             "`predicted_*` columns); the model has no fitted constant, so both halves are test data; the odd "
             "rows of atlas.csv (numbered from 1) are the declared test half.", ""]
    main = [r for r in rows if r["d"] == "2" and r["r"] == "1" and r["width"] == "0.01"]
    for i, r in enumerate(rows):
        r["half"] = "test" if i % 2 == 0 else "fit"

    def c_rows(sel):
        return [r for r in sel if r["eps"] is None and isnum(r["C"]) and isnum(r["pred_C"]) and r["pred_C"] > 0]

    lines += ["| C (exact rationals, d = 2, lambda = 0.01) | half | Q | points | median error | worst error (omega) |",
              "|---|---|---|---|---|---|"]
    for half in ("test", "fit"):
        for parity, name in ((0, "even"), (1, "odd")):
            sel = [r for r in c_rows(main) if r["half"] == half and r["Q"] is not None and r["Q"] % 2 == parity]
            if not sel:
                continue
            err = sorted((abs(r["pred_C"] / r["C"] - 1), r["omega"]) for r in sel)
            lines.append("| | %s | %s | %d | %.1f%% | %.1f%% (%s) |" % (
                half, name, len(sel), 100 * err[len(err) // 2][0], 100 * err[-1][0], err[-1][1]))
    verdict = [r for r in rows if r["pred_tail"] in ("forms", "none")]
    lines += ["", "| tail forms? | half | points | right | wrong (omega: measured, predicted) |", "|---|---|---|---|---|"]
    for half in ("test", "fit"):
        sel = [r for r in verdict if r["half"] == half]
        wrong = [r for r in sel if measured_forms(r) != (r["pred_tail"] == "forms")]
        lines.append("| | %s | %d | %.1f%% | %s |" % (half, len(sel), 100 * (1 - len(wrong) / max(1, len(sel))),
                                                    ", ".join("%s %s: %s, %s" % (r["set"], r["omega"], r["tail"], r["pred_tail"])
                                                              for r in wrong) or "-"))
    ends = [r for r in rows if r["eps"] is not None and isnum(r["pred_end"]) and (isnum(r["end_tenth"]) or
                                                                                  isnum(r["tail_end"]))]
    if ends:
        lines += ["", "The end, measured as the model defines it: the first time past the tail's start where t P falls "
                  "to a tenth of its largest value (`end_tenth`; a half: `end_half`), beside the tail-class rule's "
                  "end and its bracket [lo, hi].", "",
                  "| eps family | d | lambda | omega | measured end_tenth (end_half) | predicted end (half) | predicted / "
                  "measured | rule's end [lo, hi] |", "|---|---|---|---|---|---|---|---|"]
        for r in ends:
            ratio = "%.2f" % (r["pred_end"] / r["end_tenth"]) if isnum(r["end_tenth"]) else "-"
            lines.append("| %s | %s | %s | %s | %s (%s) | %.4g | %s | %s |" % (
                r["set"], r["d"], r["width"], r["omega"], fmt(r["end_tenth"], digits=4), fmt(r["end_half"], digits=4),
                r["pred_end"], ratio, "%.4g [%.4g, %.4g]" % (r["tail_end"], r["end_lo"], r["end_hi"])
                if isnum(r["tail_end"]) else "-"))
        both = [r for r in ends if isnum(r["end_tenth"])]
        inside = sum(abs(r["pred_end"] / r["end_tenth"] - 1) <= 0.25 for r in both)
        bracket = [r for r in ends if isnum(r["tail_end"])]
        in_bracket = sum(abs(end_check(r)) <= 0.25 for r in bracket)
        lines += ["", "Predicted ends within 25%% of the measured end_tenth: %d of %d; within 25%% of the rule's "
                  "bracket: %d of %d." % (inside, len(both), in_bracket, len(bracket))]
    other = [r for r in rows if r not in main and (isnum(r["C"]) or isnum(r["pred_C"]))]
    if other:
        lines += ["", "| other stadiums and leaks | d | lambda | omega | measured C | predicted C | ratio | tail, "
                  "predicted |", "|---|---|---|---|---|---|---|---|"]
        for r in other:
            ratio = "%.3f" % (r["pred_C"] / r["C"]) if isnum(r["C"]) and isnum(r["pred_C"]) else "-"
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s, %s |" % (
                r["set"], r["d"], r["width"], r["omega"], fmt(r["C"], r["C_err"], r["C_syst"]),
                "%.4g" % r["pred_C"] if isnum(r["pred_C"]) else "-", ratio, r["tail"], r["pred_tail"] or "-"))
    have = c_rows(rows)
    if have:
        fig, ax = plt.subplots(figsize=(6.4, 5.6))
        for parity, marker, colour in ((0, "s", "C0"), (1, "o", "C3")):
            sel = [r for r in have if r["Q"] is not None and r["Q"] % 2 == parity and r in main]
            ax.errorbar([r["pred_C"] for r in sel], [r["C"] for r in sel], yerr=[r["C_err"] for r in sel], fmt=marker,
                        ms=4, color=colour, lw=0.7, label="%s Q (d = 2, lambda = 0.01)" % ("even" if parity == 0 else "odd"))
        sel = [r for r in have if r not in main or r["Q"] is None]
        if sel:
            ax.errorbar([r["pred_C"] for r in sel], [r["C"] for r in sel], yerr=[r["C_err"] for r in sel], fmt="D",
                        ms=4, color="C2", lw=0.7, label="other d or lambda; irrationals")
        lo, hi = min(r["pred_C"] for r in have) / 1.5, max(r["pred_C"] for r in have) * 1.5
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.8, label="measured = predicted")
        ax.set_yscale("log")
        finish(fig, ax, os.path.join(docs, "C_predicted.png"), "predicted C (covering model, no fitted constant)",
               "measured C", "tail amplitude: the model against the atlas")
        lines += ["", "![C predicted](C_predicted.png)"]
    return lines


def main(argv):
    if len(argv) != 5:
        sys.exit("usage: atlas_report.py OUT DOCS PARTICLES SECONDS")
    out, docs, particles, wall = argv[1], argv[2], int(argv[3]), int(argv[4])
    os.makedirs(docs, exist_ok=True)
    rows, seconds, titles = [], 0.0, []
    for name, title, args in sets():
        if not os.path.exists(os.path.join(out, name, "scan.json")):
            continue
        r, s = rows_of(out, name)
        rows += r
        seconds += s
        titles.append((name, title, args, len(r), s))
    drawn = figures(rows, docs)
    cols = ["set", "omega", "Q", "kappa", "kappa_err", "alpha", "alpha_err", "alpha_syst", "alpha_bound", "C",
            "C_err", "C_syst", "height", "height_err", "from", "tail", "regime", "tail_end", "end_lo", "end_hi", "near",
            "t_max", "d", "r", "width", "end_half", "end_tenth", "pred_tail", "pred_C", "pred_end"]
    tmp = os.path.join(docs, ".atlas.csv.tmp")
    pandas.DataFrame([{c: r[c] for c in cols} for r in rows], columns=cols).to_csv(tmp, index=False)
    os.replace(tmp, os.path.join(docs, "atlas.csv"))
    lines = ["# The omega atlas", "",
             "Written by `scripts/atlas.sh --docs` (the scans and `scripts/atlas_report.py`); every number here "
             "is read from the scans' `table.csv` and `scan.json`. Each point: %d lines, mupo sampling, the "
             "fast-forward and population splitting on `data/study/study.toml` (d = 2, r = 1, lambda = 0.01, "
             "s_L(0) = 0). Q is the denominator of 2 r omega mod 1; C is the tail amplitude (P ~ C / t, "
             "docs/model.md \"Observables\") +- its stat. error +- its drift, or in parentheses, where t P is not "
             "flat, its height where the tail begins; alpha +- stat. +- window systematic, or `< bound`; the tail "
             "end with the range [lo, hi] the rule places it in (summary.json `tail.tail_end_range`)." % particles, "",
             "Runs: %d points, %.0f s of point wall time; the `scripts/atlas.sh` call that wrote this took %d s "
             "(a resumed call counts only what it ran) on the 2-core development machine." % (len(rows), seconds,
                                                                                             wall), "",
             "| set | points | what | point seconds |", "|---|---|---|---|"]
    for name, title, args, n, s in titles:
        lines.append("| %s | %d | %s (`%s`) | %.0f |" % (name, n, title, args, s))
    for png in drawn:
        lines += ["", "![%s](%s)" % (png[:-4].replace("_", " "), png)]
    lines += ["", "| set | omega | Q | kappa | alpha | C | tail | regime | tail end |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        alpha = fmt(r["alpha"], r["alpha_err"], r["alpha_syst"]) if isnum(r["alpha"]) else (
            "< %.2g" % r["alpha_bound"] if isnum(r["alpha_bound"]) else "-")
        regime = r["regime"] + (" (%s)" % r["near"] if r["near"] else "")
        amp = fmt(r["C"], r["C_err"], r["C_syst"])
        if amp == "-" and isnum(r["height"]):  # no flat stretch: the tail's height where it begins
            amp = "(t P = %s at t = %g)" % (fmt(r["height"], r["height_err"]), r["from"])
        end = fmt(r["tail_end"], digits=5)
        if isnum(r["end_lo"]):
            end += " [%.5g, %.5g]" % (r["end_lo"], r["end_hi"])
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["set"], r["omega"], r["Q"] if r["Q"] is not None else "-", fmt(r["kappa"], r["kappa_err"], digits=4),
            alpha, amp, r["tail"], regime, end))
    lines += prediction_section(rows, docs)
    tmp = os.path.join(docs, ".README.md.tmp")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, os.path.join(docs, "README.md"))


if __name__ == "__main__":
    main(sys.argv)
