#!/usr/bin/python3
"""The open circle's survival probability, exact from its integrable geometry, against rotleak's.

The circle is the table Bunimovich & Dettmann solved (PRL 94, 100201 (2005)): in a circle of radius 1 a flight
keeps its angle of incidence theta (p = sin theta), so each collision advances the boundary coordinate by
rho = 1/2 - theta / pi and takes the chord 2 cos theta. A particle started at s0 with momentum p (Birkhoff's
measure: s0 and p uniform) survives N collisions unless some s0 + k rho (k = 1 .. N) falls into the hole of width
eps at s = 0; so the share of s0 that survives is 1 - |union over k of (hole - k rho)| (the union of N arcs of
length eps, measured exactly by sorting their starts), and P(t) is its mean over p with N = floor(t / (2 cos theta)).
Their exact formulas are this integral expressed through the zeros of the Riemann zeta function; here it is
evaluated by the midpoint rule in p at two resolutions (their difference bounds the quadrature's error) and
compared with `rotleak simulate` (all particles created at t = 0) at a few times, in binomial standard errors.

Usage: scripts/circle_exact.py BUILD_DIR [PARTICLES (default 4000000)] [EPS (default 0.02)]
"""
import sys

import numpy as np

from scene_runs import Scratch, markdown

TIMES = (10.0, 50.0, 100.0, 200.0)


def covered(rho, n, eps):
    """|union over k = 1 .. n of [-k rho - eps/2, -k rho + eps/2] mod 1|."""
    if n <= 0:
        return 0.0
    a = np.sort(np.mod(-np.arange(1, n + 1) * rho - eps / 2, 1.0))
    gaps = np.diff(np.concatenate([a, [a[0] + 1.0]]))
    return min(1.0, float(np.sum(np.minimum(gaps, eps))))


def exact_p(t, eps, m):
    """P(t) by the midpoint rule on m points of p in (0, 1) (P is even in p)."""
    p = (np.arange(m) + 0.5) / m
    theta = np.arcsin(p)
    rho, n = 0.5 - theta / np.pi, np.floor(t / (2 * np.cos(theta))).astype(np.int64)
    return float(np.mean([1 - covered(r, k, eps) for r, k in zip(rho, n)]))


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    build = argv[1]
    particles = int(argv[2]) if len(argv) > 2 else 4000000
    eps = argv[3] if len(argv) > 3 else "0.02"
    scene = ('[table]\nkind = "circle"\nradius = "1"\n[[leaks]]\nwidth = "%s"\n[run]\nt_max = %r\n'
             '[ensemble]\ncreation_window = 0.0\n[observe]\nsurvival_dt = 1.0\n' % (eps, max(TIMES)))
    with Scratch("rotleak_circle_") as work:
        rows = {float(r["t"]): r for r in work.simulate(build, "circle", scene, particles)}
    worst, lines = 0.0, []
    for t in TIMES:
        coarse, fine = exact_p(t, float(eps), 20000), exact_p(t, float(eps), 40000)
        p, err = float(rows[t]["P"]), float(rows[t]["P_err"])
        z = (p - fine) / err
        worst = max(worst, abs(z))
        lines.append(["%g" % t, "%.5f / %.5f" % (coarse, fine), "%.5f +- %.5f" % (p, err), "%+.2f" % z])
    markdown(["t", "P exact (20000 / 40000 points in p)", "P rotleak (%d particles)" % particles,
              "(rotleak - exact) / error"], lines)
    return 0 if worst < 5 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
