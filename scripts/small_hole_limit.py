#!/usr/bin/python3
"""The small-hole limit of the escape rate on a dispersing table with finite horizon, and on one without.

Demers, Wright & Young (Commun. Math. Phys. 294 (2010)) prove that the periodic Lorentz gas with finite horizon,
opened by small holes on its scatterers, has an escape rate, and that its conditionally invariant measure tends to
the billiard's invariant measure as the holes shrink; the escape rate then tends to the hole's measure (Keller &
Liverani's small-hole expansion): in the flow's time, kappa / kappa0 -> 1, kappa0 = lambda |boundary| / (pi Area)
the small-hole rate (docs/tables.md). The next term is not derived here: it comes from the hole's own
returns into itself (Keller & Liverani's sum over returns), and the script fits two forms for it.

For the Lorentz triangle (the triangular Lorentz gas's fundamental domain, discs of radius 0.45 on a lattice of
spacing 1: finite horizon) and the Sinai billiard (side 2, disc radius 1/2: infinite horizon, its square's
wall-to-wall flights), at four hole widths lambda (a share of the outer boundary's length, the hole centred at s = 0:
the top arc's midpoint, the top side's midpoint), runs ``rotleak simulate`` as scripts/table_rates.py does (uniform
Birkhoff starts, kappa fitted on [T/2, 3 T], T = 1 / kappa0, its window systematic in the error), fits
kappa / kappa0 = a + b lambda and a + c lambda ln(1 / lambda) by weighted least squares, and prints each limit a,
its error and (a - 1) / error, with the fit's chi^2, and each form's fit with a = 1 fixed. Writes every run's numbers as CSV (docs/output.md).

Usage: scripts/small_hole_limit.py BUILD_DIR OUT.csv [PARTICLES]   (default 1000000)
"""
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table_rates import rate_row, run, write_csv  # noqa: E402  (one run, its fit and its row, as the small-hole table's)

TABLES = [
    ("lorentz", '[table]\nkind = "lorentz"\nradius = "0.45"\n'),
    ("sinai", '[table]\nkind = "sinai"\nside = "2"\nradius = "1/2"\n'),
]
WIDTHS = ("0.02", "0.01", "0.005", "0.0025")


def line_fit(xs, ys, es):
    """Weighted least squares y = a + b x: a, b, their errors, chi^2 and its degrees of freedom."""
    w = [1 / e ** 2 for e in es]
    s, sx, sy = sum(w), sum(wi * x for wi, x in zip(w, xs)), sum(wi * y for wi, y in zip(w, ys))
    sxx, sxy = sum(wi * x * x for wi, x in zip(w, xs)), sum(wi * x * y for wi, x, y in zip(w, xs, ys))
    det = s * sxx - sx * sx
    a, b = (sxx * sy - sx * sxy) / det, (s * sxy - sx * sy) / det
    chi2 = sum(wi * (y - a - b * x) ** 2 for wi, x, y in zip(w, xs, ys))
    return a, math.sqrt(sxx / det), b, math.sqrt(s / det), chi2, len(xs) - 2


def through_one(xs, ys, es):
    """Weighted least squares y = 1 + b x (the limit fixed at 1): b and chi^2 (len(xs) - 1 degrees of freedom)."""
    w = [1 / e ** 2 for e in es]
    b = sum(wi * x * (y - 1) for wi, x, y in zip(w, xs, ys)) / sum(wi * x * x for wi, x in zip(w, xs))
    return b, sum(wi * (y - 1 - b * x) ** 2 for wi, x, y in zip(w, xs, ys))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    build, out_csv = sys.argv[1], sys.argv[2]
    particles = int(sys.argv[3]) if len(sys.argv) > 3 else 1000000
    work = tempfile.mkdtemp(prefix="rotleak-small-hole-")
    lines, fits = [], []
    try:
        for name, table in TABLES:
            rows = []
            for width in WIDTHS:
                s, k0, _ = run(build, work, name, table, width, particles)
                row = rate_row(name, width, s, k0)
                row.update({"particles": particles, "collisions": s["collisions"]})
                rows.append(row)
                print("%-8s lambda %-6s kappa0 %.5g  kappa %.5g  ratio %.4f +- %.4f" % (
                    name, width, k0, row["kappa"], row["ratio"], row["ratio_err"]), flush=True)
            xs, ys, es = [float(r["width"]) for r in rows], [r["ratio"] for r in rows], [r["ratio_err"] for r in rows]
            logs = [x * math.log(1 / x) for x in xs]
            fits.append((name, (line_fit(xs, ys, es), through_one(xs, ys, es)),
                         (line_fit(logs, ys, es), through_one(logs, ys, es))))
            lines += rows
    finally:
        shutil.rmtree(work)
    write_csv(out_csv, lines)
    print("\n| table | " + " | ".join("lambda = %s" % x for x in WIDTHS) + " |\n" + "|---" * (len(WIDTHS) + 1) + "|")
    for name, _, _ in fits:
        print("| %s | %s |" % (name, " | ".join("%.4f +- %.4f" % (r["ratio"], r["ratio_err"]) for r in lines
                                                if r["table"] == name)))
    print("\n| table | next term | a (lambda -> 0) | (a - 1) / error | its coefficient | chi^2 / dof | with a = 1: "
          "coefficient, chi^2 / dof |\n|---|---|---|---|---|---|---|")
    for name, lin, log in fits:
        for form, ((a, ea, b, eb, chi2, dof), (b1, chi1)) in (("b lambda", lin), ("c lambda ln(1/lambda)", log)):
            print("| %s | %s | %.4f +- %.4f | %+.1f | %.2f +- %.2f | %.2f / %d | %.2f, %.2f / %d |" % (
                name, form, a, ea, (a - 1) / ea, b, eb, chi2, dof, b1, chi1, dof + 1))

if __name__ == "__main__":
    main()
