#!/usr/bin/python3
"""The open mushroom with a hole on its stem, its never-escaping share exact and the decay of the rest, against rotleak.

docs/tables.md, "Against the literature: the open mushroom"; Dettmann & Georgiou, J. Phys. A 44 (2011).

The mushroom: a half disc of radius R = 1 (the cap) on a centred stem of width w = 1/2 and height 1; the hole is
the whole bottom of the stem. An orbit of the cap is a chord family at a fixed distance rho from the cap's centre
(a reflection on the cap's flat base, a line through the centre, keeps rho); it crosses the base's line at
|x| >= rho, so when rho > w/2 it never enters the stem and never escapes. In Birkhoff's coordinates (s, p), with
total measure 2 |boundary| (|boundary| = pi R + 2 R + 2 h), those states are: on the arc |p| > w / (2R)
(rho = R |p|), measure pi R * 2 (1 - w / (2R)); on the two base segments, a point at |x| with |x| sqrt(1 - p^2) >
w/2, measure 2 * 2 (sqrt(R^2 - a^2) - a arccos(a / R)) (a = w/2). So P(t) -> P_inf = that measure over
2 |boundary| (0.508798 here), and everything else leaves: the chaotic part, sticky, goes algebraically.

The leading constant, derived as the stadium's (docs/model.md, "Predicting the tail from omega"): the stem's two
parallel walls hold a bouncing-ball family, orbits crossing the stem nearly horizontally and drifting along it at
their small slope p. One heading down leaves through the hole; one heading up passes the cap and comes back with
slope g p, then goes down the whole stem. The cap is integrable (a chord keeps |x0| p, its distance from the centre),
so an orbit that leaves the stem's top at x0 (moving right) meets the base's line, chord after chord, at
x0 / (1 - 2 n x0 / R) with slope p (1 - 2 n x0 / R); the first n with |x| < w/2 takes it back into the stem:
g = |1 - 2 n x0 / R|, x0 uniform over the stem's width. With G = <1/g> (0.9731 here) the stem of height h gives,
as a leak-cap gap of the stadium, P_chaotic ~ (1 + G) h^2 / (|boundary| t) for uniform starts, and for entries
through the hole K = (1 + G) h^2 (an entry with vertical speed u lives h (1 + 1/g) / u, P(u < e) = e^2 / 2, and
<(1 + 1/g)^2> = 2 (1 + G) because <1/g^2> = 1: the cap passage keeps the measure; the script prints both means).
What the model leaves out: the cap's own sticky orbits (chords just inside rho = w/2, near the marginally unstable
periodic orbits of Dettmann & Georgiou), and the next order (the cap passage's own time, the bounce grid).

Two runs: particles started uniformly (P(t) against P_inf at a few times, binomial errors), and particles that
enter through the hole (ensemble.enter_through; all of them chaotic: P -> 0), whose escapes within windows
[t1, t2) estimate K in P(t) ~ K / t^2 (E[count] = N K (1/t1^2 - 1/t2^2), the count Poisson): one K for every
window is the algebraic law t^-2 for entries, t^-1 for the uniform starts' chaotic part. All particles are created
at t = 0.

Usage: scripts/mushroom_exact.py BUILD_DIR [UNIFORM_PARTICLES (default 2000000)] [ENTERING_PARTICLES (default
100000000)]. Prints two Markdown tables; exits 1 if P(1000) lies more than 5 errors from P_inf.
"""
import math
import sys

from scene_runs import Scratch, arguments, markdown

R, W, H = 1.0, 0.5, 1.0
BOUNDARY = math.pi * R + 2 * R + 2 * H
A = W / 2
P_INF = (2 * math.pi * R * (1 - A / R) + 4 * (math.sqrt(R * R - A * A) - A * math.acos(A / R))) / (2 * BOUNDARY)


def cap_return(x0):
    """The slope factor g of a stem orbit that leaves the stem's top at x0 and comes back (module docstring)."""
    n = 1
    while abs(1 - 2 * n * x0 / R) * A <= abs(x0):
        n += 1
    return abs(1 - 2 * n * x0 / R)


def cap_means(points=400000):
    """<1/g> and <1/g^2> over x0 uniform in [-w/2, w/2] (midpoints: pieces smooth between the few breakpoints)."""
    g = [cap_return(-A + 2 * A * (i + 0.5) / points) for i in range(points)]
    return sum(1 / x for x in g) / points, sum(1 / (x * x) for x in g) / points

SCENE = """[table]
kind = "mushroom"
radius = "1"
stem_width = "1/2"
stem_height = "1"

[[leaks]]
width = "(1/2)/(4+pi)"
start = "1/2"

[ensemble]
creation_window = 0.0

[run]
t_max = %r
"""

TIMES = (100.0, 300.0, 1000.0)
WINDOWS = ((100.0, 200.0), (200.0, 400.0), (400.0, 800.0), (800.0, 1600.0))


def main(argv):
    args = arguments(argv, __doc__, 2000000, 100000000)
    if args is None:
        return 2
    build, (n_uniform, n_entry) = args
    with Scratch("rotleak_mushroom_") as work:
        uniform = {float(r["t"]): r for r in work.simulate(build, "uniform", SCENE % max(TIMES), n_uniform)}
        entry = work.simulate(build, "enter", SCENE % WINDOWS[-1][1], n_entry,
                              ["ensemble.enter_through=0", "ensemble.seed=2"])
    g_mean, g2_mean = cap_means()
    k_model = (1 + g_mean) * H * H
    print("cap passage: G = <1/g> = %.4f, <1/g^2> = %.6f; model c = (1 + G) h^2 / |boundary| = %.4f, K = (1 + G) h^2 "
          "= %.4f\n" % (g_mean, g2_mean, k_model / BOUNDARY, k_model))
    z_last, lines = 0.0, []
    for t in TIMES:
        p, err = float(uniform[t]["P"]), float(uniform[t]["P_err"])
        z_last = (p - P_INF) / err
        model = P_INF + k_model / BOUNDARY / t
        lines.append(["%g" % t, "%.5f +- %.5f" % (p, err), "%.6f" % P_INF, "%+.2f" % z_last, "%.5f" % model,
                      "%+.2f" % ((p - model) / err)])
    markdown(["t", "P rotleak (%d particles, uniform starts)" % n_uniform, "P_inf exact", "(P - P_inf) / error",
              "P_inf + c / t", "(P - model) / error"], lines)
    at = {float(r["t"]): int(r["survivors"]) for r in entry}
    lines = []
    for t1, t2 in WINDOWS:
        n = at[t1] - at[t2]
        scale = n_entry * (1 / t1 ** 2 - 1 / t2 ** 2)
        k, err = n / scale, math.sqrt(max(n, 1)) / scale
        lines.append(["[%g, %g)" % (t1, t2), "%d" % n, "%.3f +- %.3f" % (k, err), "%.3f" % k_model,
                      "%+.2f" % ((k - k_model) / err)])
    print()
    markdown(["window", "escapes (%.0e entering)" % n_entry, "K in P ~ K / t^2", "model (1 + G) h^2",
              "(K - model) / error"], lines)
    return 0 if abs(z_last) < 5 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
